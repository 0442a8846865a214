// A compare directory's error-time chart (docs/design.md §11): ms_per_frame against e_cd_x1e3
// from compare.csv, log-log, one colour per method, frontier runs outlined and joined per scene.
// Hovering a point shows its row; a run whose rollout was kept opens it against its reference.
const PALETTE = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22",
  "#17becf"];
const SVG = "http://www.w3.org/2000/svg";

function element(name, attributes = {}, parent = null) {
  const node = document.createElementNS(SVG, name);
  for (const [key, value] of Object.entries(attributes)) node.setAttribute(key, value);
  if (parent) parent.append(node);
  return node;
}

// Log axis ticks: the powers of ten in [low, high], with 2 and 5 when that gives too few.
function logTicks(low, high) {
  const ticks = [];
  for (const steps of [[1], [1, 2, 5]]) {
    ticks.length = 0;
    for (let p = Math.floor(Math.log10(low)); p <= Math.ceil(Math.log10(high)); ++p)
      for (const m of steps) if (m * 10 ** p >= low && m * 10 ** p <= high) ticks.push(m * 10 ** p);
    if (ticks.length >= 3) break;
  }
  return ticks;
}

function runsOf(table) {
  const column = Object.fromEntries(table.columns.map((name, k) => [name, k]));
  return table.rows.map((row, index) => {
    const cell = (name) => row.cells[column[name]] ?? "";
    return {
      index, row, columns: table.columns,
      method: cell("method"), budget: cell("N"), scene: `${cell("resolution")} ${cell("motion")}`,
      ms: parseFloat(cell("ms_per_frame")), error: parseFloat(cell("e_cd_x1e3")), frontier: cell("frontier") === "yes",
    };
  });
}

function showTooltip(tooltip, run, event) {
  const table = document.createElement("table");
  run.columns.forEach((name, k) => {
    if (run.row.cells[k] === "") return;
    const line = table.insertRow();
    line.insertCell().textContent = name;
    line.insertCell().textContent = run.row.cells[k];
  });
  if (run.row.rollout) table.insertRow().insertCell().textContent = "click: play the rollout";
  tooltip.replaceChildren(table);
  tooltip.hidden = false;
  tooltip.style.left = `${event.clientX + 14}px`;
  tooltip.style.top = `${Math.max(4, event.clientY - tooltip.offsetHeight / 2)}px`;
}

function drawChart(container, tooltip, runs, methods) {
  const width = 900, height = 520, margin = { left: 70, right: 170, top: 20, bottom: 50 };
  // A run with e_CD 0 (the Newton reference itself) sits on the bottom edge of the log axis.
  const plotted = runs.filter((r) => r.ms > 0 && Number.isFinite(r.error) && r.error >= 0);
  const positive = plotted.filter((r) => r.error > 0);
  const svg = element("svg", { width, height, viewBox: `0 0 ${width} ${height}` });
  container.replaceChildren(svg);
  if (plotted.length === 0) {
    element("text", { x: width / 2, y: height / 2, "text-anchor": "middle" }, svg).textContent = "no run with an error to plot";
    return plotted.length;
  }
  const extent = (values) => [Math.min(...values) / 1.5, Math.max(...values) * 1.5];
  const [x0, x1] = extent(plotted.map((r) => r.ms));
  const [y0, y1] = positive.length ? extent(positive.map((r) => r.error)) : [1e-3, 1];
  const x = (v) => margin.left + ((Math.log(v) - Math.log(x0)) / (Math.log(x1) - Math.log(x0))) * (width - margin.left - margin.right);
  const y = (v) => (v <= y0 ? height - margin.bottom
    : height - margin.bottom - ((Math.log(v) - Math.log(y0)) / (Math.log(y1) - Math.log(y0))) * (height - margin.top - margin.bottom));
  const axes = element("g", { "font-size": 11, fill: "#444" }, svg);
  for (const t of logTicks(x0, x1)) {
    element("line", { x1: x(t), x2: x(t), y1: margin.top, y2: height - margin.bottom, stroke: "#eee" }, axes);
    element("text", { x: x(t), y: height - margin.bottom + 16, "text-anchor": "middle" }, axes).textContent = t;
  }
  for (const t of logTicks(y0, y1)) {
    element("line", { x1: margin.left, x2: width - margin.right, y1: y(t), y2: y(t), stroke: "#eee" }, axes);
    element("text", { x: margin.left - 6, y: y(t) + 4, "text-anchor": "end" }, axes).textContent = t;
  }
  element("rect", { x: margin.left, y: margin.top, width: width - margin.left - margin.right,
    height: height - margin.top - margin.bottom, fill: "none", stroke: "#999" }, axes);
  element("text", { x: (margin.left + width - margin.right) / 2, y: height - 12, "text-anchor": "middle" }, axes)
    .textContent = "ms per frame (log)";
  element("text", { x: 16, y: (margin.top + height - margin.bottom) / 2, "text-anchor": "middle",
    transform: `rotate(-90 16 ${(margin.top + height - margin.bottom) / 2})` }, axes).textContent = "e_CD \u00d7 10\u00b3 (log)";

  // The frontier of each scene, as a line from its fastest run to its most accurate.
  const scenes = [...new Set(plotted.map((r) => r.scene))];
  for (const scene of scenes) {
    const frontier = plotted.filter((r) => r.frontier && r.scene === scene).sort((a, b) => a.ms - b.ms);
    if (frontier.length > 1)
      element("polyline", { points: frontier.map((r) => `${x(r.ms)},${y(r.error)}`).join(" "), fill: "none",
        stroke: "#333", "stroke-dasharray": "4 3" }, svg);
  }
  for (const run of plotted) {
    const colour = PALETTE[methods.indexOf(run.method) % PALETTE.length];
    const group = element("g", { class: run.row.rollout ? "point kept" : "point" }, svg);
    if (run.row.rollout) element("circle", { cx: x(run.ms), cy: y(run.error), r: 9, fill: "none", stroke: colour }, group);
    element("circle", { cx: x(run.ms), cy: y(run.error), r: run.frontier ? 5.5 : 4, fill: colour,
      stroke: run.frontier ? "#000" : "#fff", "stroke-width": run.frontier ? 1.5 : 1 }, group);
    group.addEventListener("mousemove", (event) => showTooltip(tooltip, run, event));
    group.addEventListener("mouseleave", () => (tooltip.hidden = true));
    if (run.row.rollout) group.addEventListener("click", () => (location.href = `/?run=${run.index}`));
  }
  const legend = element("g", { "font-size": 12 }, svg);
  methods.forEach((method, k) => {
    const row = element("g", { transform: `translate(${width - margin.right + 16}, ${margin.top + 10 + 18 * k})` }, legend);
    element("circle", { r: 5, fill: PALETTE[k % PALETTE.length] }, row);
    element("text", { x: 10, y: 4 }, row).textContent = method;
  });
  const note = element("g", { "font-size": 11, fill: "#444",
    transform: `translate(${width - margin.right + 11}, ${margin.top + 30 + 18 * methods.length})` }, legend);
  element("circle", { r: 5, fill: "#fff", stroke: "#000", "stroke-width": 1.5 }, note);
  element("text", { x: 10, y: 4 }, note).textContent = "frontier";
  return plotted.length;
}

export async function showCompareChart(table) {
  const runs = runsOf(table);
  const methods = [...new Set(runs.map((r) => r.method))];
  const section = document.getElementById("compare");
  const filter = document.getElementById("scene-filter");
  const status = document.getElementById("status");
  section.hidden = false;
  document.getElementById("title").textContent = "fnopt compare";
  document.getElementById("subtitle").textContent = `${table.directory}: ${runs.length} runs, ` +
    `${runs.filter((r) => r.row.rollout).length} with kept rollouts`;
  const scenes = [...new Set(runs.map((r) => r.scene))];
  filter.replaceChildren(...["all", ...scenes].map((s) => new Option(s === "all" ? "every scene" : s, s)));
  const draw = () => {
    const shown = runs.filter((r) => filter.value === "all" || r.scene === filter.value);
    const plotted = drawChart(document.getElementById("chart"), document.getElementById("tooltip"), shown, methods);
    status.textContent = plotted < shown.length
      ? `${shown.length - plotted} run(s) not plotted: no error (diverged or failed); see compare.csv` : "";
  };
  filter.onchange = draw;
  draw();
}
