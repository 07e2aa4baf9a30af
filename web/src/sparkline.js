// Small plots on a canvas: a tile's force sparkline and the trainee view's
// force-time and force-depth plots (the 1 kHz peaks the frames carry).

export class History {
  constructor(capacity) {
    this.capacity = capacity;
    this.points = [];  // [x, y]
  }
  add(x, y) {
    this.points.push([x, y]);
    if (this.points.length > this.capacity) this.points.shift();
  }
  clear() {
    this.points = [];
  }
}

// Draws the points as a line; axes from their range (y from 0).
export function drawPlot(canvas, points, {color = '#d33', xLabel = '', yLabel = '', scatter = false} = {}) {
  const ctx = canvas.getContext('2d');
  const w = canvas.width, h = canvas.height;
  ctx.clearRect(0, 0, w, h);
  if (xLabel || yLabel) {
    ctx.fillStyle = '#666';
    ctx.font = '11px sans-serif';
    ctx.fillText(yLabel, 4, 12);
    ctx.fillText(xLabel, w - ctx.measureText(xLabel).width - 4, h - 4);
  }
  if (points.length < 2) return;
  let x0 = Infinity, x1 = -Infinity, y1 = 1e-9;
  for (const [x, y] of points) {
    x0 = Math.min(x0, x);
    x1 = Math.max(x1, x);
    y1 = Math.max(y1, y);
  }
  const sx = (x) => ((x - x0) / Math.max(x1 - x0, 1e-9)) * (w - 8) + 4;
  const sy = (y) => h - 4 - (y / y1) * (h - 20);
  ctx.strokeStyle = color;
  ctx.fillStyle = color;
  ctx.beginPath();
  points.forEach(([x, y], i) => {
    if (scatter)
      ctx.fillRect(sx(x) - 1, sy(y) - 1, 2, 2);
    else if (i === 0)
      ctx.moveTo(sx(x), sy(y));
    else
      ctx.lineTo(sx(x), sy(y));
  });
  if (!scatter) ctx.stroke();
  if (yLabel) {
    ctx.fillStyle = '#666';
    ctx.fillText(`max ${y1.toFixed(2)}`, w - 70, 12);
  }
}
