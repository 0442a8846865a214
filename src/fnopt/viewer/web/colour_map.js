// The colour map of the cloth's per-vertex values and of the colour bar (docs/design.md §11):
// viridis, perceptually uniform and readable in grey, as a degree-6 polynomial fit.
const COEFFICIENTS = [
  [0.2777273272234177, 0.005407344544966578, 0.3340998053353061],
  [0.1050930431085774, 1.404613529898575, 1.384590162594685],
  [-0.3308618287255563, 0.214847559468213, 0.09509516302823659],
  [-4.634230498983486, -5.799100973351585, -19.33244095627987],
  [6.228269936347081, 14.17993336680509, 56.69055260068105],
  [4.776384997670288, -13.74514537774601, -65.35303263337234],
  [-5.435455855934631, 4.645852612178535, 26.3124352495832],
];

// Vertices with no value (no reference frame at that time) are grey.
export const NO_VALUE = [0.6, 0.6, 0.6];

// [r, g, b] in 0..1 for `t` in 0..1 (clamped).
export function viridis(t) {
  const x = Math.min(1, Math.max(0, t));
  const rgb = [0, 0, 0];
  for (let c = 0; c < 3; ++c) {
    let value = 0;
    for (let k = COEFFICIENTS.length - 1; k >= 0; --k) value = value * x + COEFFICIENTS[k][c];
    rgb[c] = Math.min(1, Math.max(0, value));
  }
  return rgb;
}

export function drawColourRamp(canvas) {
  const context = canvas.getContext("2d");
  for (let x = 0; x < canvas.width; ++x) {
    const [r, g, b] = viridis(x / (canvas.width - 1));
    context.fillStyle = `rgb(${255 * r}, ${255 * g}, ${255 * b})`;
    context.fillRect(x, 0, 1, canvas.height);
  }
}
