// Small plots of a rollout's per-step series against time, with a cursor at the shown frame
// (docs/design.md §11). ARCSim files have no per-step data: then there are no plots.
const SERIES = {
  step_max_strain: { title: "max edge strain", unit: "%", scale: 100 },
  step_energy: { title: "energy", unit: "J", scale: 1 },
  step_iterations: { title: "iterations per step", unit: "", scale: 1 },
  step_wall_ms: { title: "time per step", unit: "ms", scale: 1 },
};

function formatted(value) {
  return Math.abs(value) >= 1000 || (Math.abs(value) < 0.01 && value !== 0) ? value.toExponential(2) : value.toPrecision(3);
}

function drawPlot(canvas, times, values, time) {
  const ratio = window.devicePixelRatio || 1;
  const width = canvas.clientWidth, height = canvas.clientHeight;
  if (canvas.width !== Math.round(width * ratio)) {
    canvas.width = Math.round(width * ratio);
    canvas.height = Math.round(height * ratio);
  }
  const context = canvas.getContext("2d");
  context.setTransform(ratio, 0, 0, ratio, 0, 0);
  context.clearRect(0, 0, width, height);
  const finite = values.filter(Number.isFinite);
  if (finite.length === 0) return;
  const low = Math.min(...finite), high = Math.max(...finite);
  const span = high > low ? high - low : 1;
  const left = 48, right = width - 4, top = 6, bottom = height - 14;
  const t0 = times[0], t1 = times[times.length - 1] > t0 ? times[times.length - 1] : t0 + 1;
  const x = (t) => left + ((t - t0) / (t1 - t0)) * (right - left);
  const y = (v) => bottom - ((v - low) / span) * (bottom - top);
  context.font = "10px DejaVu Sans, sans-serif";
  context.fillStyle = "#666";
  context.textAlign = "right";
  context.fillText(formatted(high), left - 4, top + 8);
  context.fillText(formatted(low), left - 4, bottom);
  context.textAlign = "left";
  context.fillText(`${t0.toFixed(2)} s`, left, height - 2);
  context.textAlign = "right";
  context.fillText(`${t1.toFixed(2)} s`, right, height - 2);
  context.strokeStyle = "#ccc";
  context.strokeRect(left, top, right - left, bottom - top);
  context.strokeStyle = "#1f77b4";
  context.beginPath();
  values.forEach((v, k) => {
    if (Number.isFinite(v)) k === 0 ? context.moveTo(x(times[k]), y(v)) : context.lineTo(x(times[k]), y(v));
  });
  context.stroke();
  context.strokeStyle = "#d62728";
  context.beginPath();
  context.moveTo(x(time), top);
  context.lineTo(x(time), bottom);
  context.stroke();
}

// `meta.series` holds each dataset's values per step; step k ends at meta.times[k + 1].
export function createSeriesPlots(container, meta) {
  container.replaceChildren();
  const stepTimes = meta.times.slice(1);
  const plots = [];
  for (const [name, raw] of Object.entries(meta.series)) {
    const info = SERIES[name];
    if (!info) continue;
    const values = raw.map((v) => (v === null ? NaN : v * info.scale));
    const figure = document.createElement("figure");
    const caption = document.createElement("figcaption");
    caption.textContent = info.unit ? `${info.title} (${info.unit})` : info.title;
    const canvas = document.createElement("canvas");
    figure.append(caption, canvas);
    container.append(figure);
    plots.push({ canvas, values });
  }
  container.hidden = plots.length === 0;
  return {
    setTime(time) {
      for (const plot of plots) drawPlot(plot.canvas, stepTimes, plot.values, time);
    },
  };
}
