// What the Chromium and the Firefox tests share: the run's environment
// (set by tests/integration/web_console.sh) and checks of the page.
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { join } from "node:path";

export const url = process.env.HAPSIM_WEB_URL;
export const sessions = process.env.HAPSIM_SESSIONS.split(",");
export const shots = process.env.HAPSIM_SHOTS || ".";
export const token = (who) => readFileSync(join(process.env.HAPSIM_TOKENS, `${who}.token`), "utf8").trim();

// Runs in the page (pass it to page.evaluate): the 3D view's pixels and the
// tool tip's projection, sampled in one go (the same drawing).
export function sampleView() {
  const c = document.getElementById("view3d");
  const tip = window.hapsim.view.projectedTip();
  const probe = document.createElement("canvas");
  probe.width = c.clientWidth;
  probe.height = c.clientHeight;
  const ctx = probe.getContext("2d");
  ctx.drawImage(c, 0, 0, probe.width, probe.height);
  const all = ctx.getImageData(0, 0, probe.width, probe.height).data;
  // Pixels of the tissue: reddish, unlike the grey background (#f4f4f4).
  let tissue = 0;
  for (let i = 0; i < all.length; i += 4) tissue += all[i] > all[i + 2] + 30 && all[i] > all[i + 1] + 20 ? 1 : 0;
  // The tool is blue: the pixels around two points of its shaft above the
  // tissue (the tip itself may be inside it, hidden).
  let blue = 0;
  for (const fraction of [0.75, 0.95]) {
    const at = window.hapsim.view.projectedShaft(fraction);
    for (let dy = -3; dy <= 3; ++dy) {
      for (let dx = -3; dx <= 3; ++dx) {
        const x = Math.round(at.x + dx), y = Math.round(at.y + dy);
        if (x < 0 || y < 0 || x >= probe.width || y >= probe.height) continue;
        const [r, g, b] = ctx.getImageData(x, y, 1, 1).data;
        if (b > r + 40 && b > g + 20) ++blue;
      }
    }
  }
  return { tissueShare: tissue / (probe.width * probe.height), blue, tip, width: probe.width, height: probe.height };
}

export function assertViewShowsTissueAndNeedle(sample) {
  assert.ok(sample.tissueShare > 0.02, `the tissue is drawn (${(100 * sample.tissueShare).toFixed(1)} % of the view)`);
  assert.ok(sample.tip.x > 0 && sample.tip.x < sample.width && sample.tip.y > 0 && sample.tip.y < sample.height,
    `the tool tip projects into the view (${JSON.stringify(sample.tip)})`);
  assert.ok(sample.blue >= 6, `the needle is drawn where its pose projects (${sample.blue} blue pixels)`);
}

// Runs in the page: how many pixels of the force-time plot are drawn.
export function plotInk() {
  const c = document.getElementById("plot-time");
  const d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
  let n = 0;
  for (let i = 3; i < d.length; i += 4) n += d[i] > 0 ? 1 : 0;
  return n;
}
