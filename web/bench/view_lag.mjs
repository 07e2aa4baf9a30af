// How far the browser's trainee view lags behind the server when the tab is
// slow (run by tests/bench/web_console.sh; docs/performance.md, "The web
// console"). Opens a trainee's view in Debian's Chromium, lets it run
// unthrottled, then slows the page's CPU with the DevTools protocol
// (Emulation.setCPUThrottlingRate) and keeps watching. A drawing's lag is
// when its JavaScript finished drawing minus when the server encoded the
// frame it shows (the frame's sent_unix_s; server and browser share this
// machine's clock). Prints JSON: drawings per second and lag p50/p99/max
// per phase, the drawing's own time, and the page's messages.
// Environment as web/test/console.test.mjs, plus HAPSIM_SESSION, and
// THROTTLE (e.g. "4 10"), PHASE_S; PROFILE=1 adds each phase's top
// functions by self time (the page's JavaScript profile) to stderr.
import { readFileSync } from "node:fs";
import { join } from "node:path";
import { chromium } from "playwright-core";

const env = process.env;
const phaseS = Number(env.PHASE_S || 8);
const rates = (env.THROTTLE || "4 10").split(" ").map(Number);
// A page throttled past what this machine can serve may stop answering the
// DevTools protocol: then the phases done so far are printed, and that one
// is named as not answering.
const phases = [];
let current = null;
setTimeout(() => {
  console.error(`view_lag: no answer from the page in time (${current})`);
  console.log(JSON.stringify(summary().concat([{ name: current, no_answer: true }])));
  process.exit(1);
}, (rates.length + 1) * phaseS * 1000 + 90000).unref();
const browser = await chromium.launch({
  executablePath: env.HAPSIM_CHROMIUM || "/usr/bin/chromium",
  args: ["--no-sandbox", "--disable-quic", "--no-first-run", "--disable-background-networking",
    "--disable-component-update", "--disable-sync", `--ignore-certificate-errors-spki-list=${env.HAPSIM_WEB_SPKI}`,
    "--use-angle=swiftshader", "--enable-unsafe-swiftshader"],
});
const page = await browser.newPage({ viewport: { width: 1366, height: 768 } });
await page.goto(env.HAPSIM_WEB_URL);
await page.fill("#token", readFileSync(join(env.HAPSIM_TOKENS, "instructor.token"), "utf8").trim());
await page.click("#login button[type=submit]");
await page.waitForSelector(`.tile[data-session="${env.HAPSIM_SESSION}"]`);
await page.click(`.tile[data-session="${env.HAPSIM_SESSION}"]`);
await page.waitForFunction(() => window.hapsim.framesApplied > 10);
console.error("view open; measuring");
const cdp = await page.context().newCDPSession(page);

async function phase(name, rate) {
  console.error(`phase ${name}`);
  current = name;
  await cdp.send("Emulation.setCPUThrottlingRate", { rate });
  if (env.PROFILE) {
    await cdp.send("Profiler.enable");
    await cdp.send("Profiler.start");
  }
  const from = await page.evaluate(() => [performance.timeOrigin + performance.now(), window.hapsim.connection.handlingMs,
    window.hapsim.connection.messages]);
  await page.waitForTimeout(phaseS * 1000);
  await cdp.send("Emulation.setCPUThrottlingRate", { rate: 1 });  // a throttled page answers slowly
  if (env.PROFILE) printProfile(name, (await cdp.send("Profiler.stop")).profile);
  const [log, handlingMs, messages] = await page.evaluate(([t0, ms0, n0]) =>
    [window.hapsim.frameLog.filter(([at]) => at >= t0), window.hapsim.connection.handlingMs - ms0,
      window.hapsim.connection.messages - n0], from);
  return { name, rate, log, handlingMs, messages };
}
// Self time per function (name, file:line), the top 15, as milliseconds per second of the phase.
function printProfile(name, profile) {
  const dt = new Map(profile.nodes.map((n) => [n.id, 0]));
  for (let i = 0; i < profile.samples.length; ++i) {
    dt.set(profile.samples[i], dt.get(profile.samples[i]) + (profile.timeDeltas[i] || 0) / 1000);
  }
  const self = new Map();
  for (const n of profile.nodes) {
    const f = n.callFrame;
    const key = `${f.functionName || "(anonymous)"} ${f.url.split("/").pop()}:${f.lineNumber + 1}`;
    self.set(key, (self.get(key) || 0) + dt.get(n.id));
  }
  const top = [...self].sort((a, b) => b[1] - a[1]).slice(0, 15);
  console.error(`profile of ${name} (ms per s):`);
  for (const [key, ms] of top) console.error(`  ${(ms / phaseS).toFixed(1).padStart(7)}  ${key}`);
}

const pct = (sorted, q) => sorted[Math.min(sorted.length - 1, Math.floor(q * sorted.length))];
function summary() {
  return phases.map(({ name, rate, log, handlingMs, messages }) => {
    const lags = log.map(([at, sent]) => at - sent).sort((a, b) => a - b);
    const draws = log.map(([, , ms]) => ms).sort((a, b) => a - b);
    // LAG_SERIES=1: every drawing as [lag, ms since the previous drawing, drawing ms], to stderr.
    if (env.LAG_SERIES) console.error(name, JSON.stringify(log.map(([at, sent, ms], i) =>
      [Math.round(at - sent), Math.round(i ? at - log[i - 1][0] : 0), Math.round(ms)])));
    return { name, rate, drawings: log.length, fps: log.length / phaseS, lag_ms_p50: pct(lags, 0.5),
      lag_ms_p99: pct(lags, 0.99), lag_ms_max: lags[lags.length - 1], draw_ms_p50: pct(draws, 0.5),
      draw_ms_p99: pct(draws, 0.99), messages_per_s: messages / phaseS, ms_per_message: handlingMs / messages };
  });
}

phases.push(await phase("unthrottled", 1));
for (const r of rates) phases.push(await phase(`throttled ${r}x`, r));
const out = summary();
console.log(JSON.stringify(out));
await browser.close();
