// The class console in a real browser (Debian's Chromium, driven by
// playwright-core), against a running hapsim-server with a class whose
// trainees hapsim-load drives. tests/integration/web_console.sh starts
// everything and passes, in the environment:
//   HAPSIM_WEB_URL        https://127.0.0.1:PORT/
//   HAPSIM_WEB_SPKI       the server certificate's SPKI hash (Chromium trusts exactly it)
//   HAPSIM_TOKENS         the class's token folder (instructor, observer, trainee1 ...)
//   HAPSIM_SESSIONS       the class's session ids, comma-separated
//   HAPSIM_RESTART        a command that restarts the server on the same ports
//   HAPSIM_SHOTS          where to save screenshots
import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { execFile } from "node:child_process";
import { readFileSync } from "node:fs";
import { join } from "node:path";
import { promisify } from "node:util";
import { chromium } from "playwright-core";
import { assertViewShowsTissueAndNeedle, plotInk, sampleView, sessions, shots, token, url } from "./page_checks.mjs";

let browser;

const execFileAsync = promisify(execFile);

const launch = (extraArgs) => chromium.launch({
  executablePath: process.env.HAPSIM_CHROMIUM || "/usr/bin/chromium",
  args: [
    "--no-sandbox", "--disable-quic", "--no-first-run", "--disable-background-networking",
    "--disable-component-update", "--disable-sync",
    `--ignore-certificate-errors-spki-list=${process.env.HAPSIM_WEB_SPKI}`, ...extraArgs,
  ],
});

before(async () => {
  browser = await launch(["--use-angle=swiftshader", "--enable-unsafe-swiftshader"]);  // WebGL without a GPU
});
after(async () => browser && (await browser.close()));

async function login(who, viewport = { width: 1366, height: 768 }, inBrowser = browser) {
  const page = await inBrowser.newPage({ viewport });
  const errors = [];
  page.on("pageerror", (e) => errors.push(e.message));
  page.errors = errors;
  const response = await page.goto(url);
  assert.equal(response.status(), 200);
  assert.ok(page.url().startsWith("https://"), "served over TLS");
  await page.fill("#token", who === "garbage" ? "garbage-token" : token(who));
  await page.click("#login button[type=submit]");
  return page;
}

const tileTicks = (page, id) =>
  page.$eval(`.tile[data-session="${id}"]`, (e) => Number(e.dataset.ticks || 0));

test("a garbage token is refused and the page says so", async () => {
  const page = await login("garbage");
  await page.waitForFunction(() => document.querySelector("#login-error").textContent.includes("Refused"));
  assert.match(await page.textContent("#login-error"), /unknown token/);
  assert.equal(await page.isHidden("#console"), true);
  await page.close();
});

test("every trainee's tile appears and updates while the class runs", async () => {
  const page = await login("instructor");
  for (const id of sessions) await page.waitForSelector(`.tile[data-session="${id}"]`, { timeout: 10000 });
  const first = await tileTicks(page, sessions[0]);
  await page.waitForTimeout(1000);
  for (const id of sessions) assert.ok((await tileTicks(page, id)) > 0, `${id} ticks`);
  assert.ok((await tileTicks(page, sessions[0])) > first, "the tiles update");
  await page.waitForFunction(
    () => [...document.querySelectorAll(".tile .device")].every((d) => d.dataset.on === "true"),
    null, { timeout: 10000 });
  await page.screenshot({ path: join(shots, "console_tiles.png") });
  assert.deepEqual(page.errors, []);
  await page.close();
});

test("opening a trainee draws the tissue, and the needle where the tool pose projects", async () => {
  const page = await login("instructor");
  await page.waitForSelector(`.tile[data-session="${sessions[0]}"]`);
  await page.click(`.tile[data-session="${sessions[0]}"]`);
  // A frame with the tool in it: the device is streaming.
  await page.waitForFunction(() => window.hapsim.view && window.hapsim.view.projectedTip() !== null, null, { timeout: 10000 });
  await page.waitForFunction(() => window.hapsim.framesApplied > 30, null, { timeout: 10000 });
  const canvas = await page.$("#view3d");
  const box = await canvas.boundingBox();
  const sample = await page.evaluate(sampleView);  // the canvas and the tip's projection in one go
  await page.screenshot({ path: join(shots, "console_trainee.png") });
  assert.ok(box.width > 300 && box.height > 150, "a usable 3D view on a 1366x768 screen");
  assertViewShowsTissueAndNeedle(sample);
  assert.deepEqual(page.errors, []);
  await page.close();
});

test("without WebGL the page says so, and plots and controls still work", async () => {
  const noGl = await launch(["--disable-webgl", "--disable-3d-apis"]);
  try {
    const page = await login("instructor", undefined, noGl);
    await page.waitForSelector(`.tile[data-session="${sessions[0]}"]`);
    await page.click(`.tile[data-session="${sessions[0]}"]`);
    await page.waitForFunction(() => window.hapsim.framesApplied > 30, null, { timeout: 10000 });
    assert.match(await page.textContent("#message"), /no 3D view in this browser/);
    assert.equal(await page.isHidden("#view3d"), true);
    await page.waitForTimeout(300);  // plots are drawn at 10 Hz
    const ink = await page.evaluate(plotInk);
    assert.ok(ink > 200, `the force-time plot is drawn (${ink} pixels)`);
    assert.equal(await page.isDisabled("#controls button[data-action=pause]"), false);
    assert.deepEqual(page.errors, []);
  } finally {
    await noGl.close();
  }
});

// The camera about the view's target: azimuth around z (up) [rad] and distance [m].
const orbit = (page) => page.evaluate(() => {
  const v = window.hapsim.view;
  const d = v.camera.position.clone().sub(v.controls.target);
  return { azimuth: Math.atan2(d.y, d.x), distance: d.length(), height: v.canvas.clientHeight };
});

// A touch gesture as the screen reports it: each finger from its start to
// its end point in `steps` moves (CSS pixels).
async function touchGesture(cdp, fingers, steps = 10) {
  const at = (k) => fingers.map(([[x0, y0], [x1, y1]], id) =>
    ({ x: x0 + ((x1 - x0) * k) / steps, y: y0 + ((y1 - y0) * k) / steps, id }));
  await cdp.send("Input.dispatchTouchEvent", { type: "touchStart", touchPoints: at(0) });
  for (let k = 1; k <= steps; ++k) await cdp.send("Input.dispatchTouchEvent", { type: "touchMove", touchPoints: at(k) });
  await cdp.send("Input.dispatchTouchEvent", { type: "touchEnd", touchPoints: [] });
}

test("on a tablet: the class fits, a tap opens a trainee, one finger turns the view, two zoom it", async () => {
  const tablet = await browser.newContext(
    { viewport: { width: 768, height: 1024 }, hasTouch: true, isMobile: true, deviceScaleFactor: 2 });
  try {
    const page = await tablet.newPage();
    const errors = [];
    page.on("pageerror", (e) => errors.push(e.message));
    await page.goto(url);
    await page.fill("#token", token("instructor"));
    await page.tap("#login button[type=submit]");
    for (const id of sessions) await page.waitForSelector(`.tile[data-session="${id}"]`, { timeout: 10000 });
    const overflow = await page.evaluate(() => document.documentElement.scrollWidth - window.innerWidth);
    assert.ok(overflow <= 0, `nothing wider than the screen (${overflow} px over)`);
    await page.tap(`.tile[data-session="${sessions[0]}"]`);
    await page.waitForFunction(() => window.hapsim.framesApplied > 30, null, { timeout: 10000 });
    const view = await (await page.$("#view3d")).boundingBox();
    const plot = await (await page.$("#plot-time")).boundingBox();
    assert.ok(view.width > 700 && view.height > 400, `the 3D view fills the width (${JSON.stringify(view)})`);
    assert.ok(plot.y >= view.y + view.height, "the plots below it, not squeezed beside it");
    // Fingers, not a mouse: every control at least 44 px tall.
    for (const selector of ["#controls button[data-action=pause]", "#close-detail", "#trials", "#push", "#push-scene"]) {
      const box = await (await page.$(selector)).boundingBox();
      assert.ok(box.height >= 44, `${selector} is ${box.height} px tall`);
    }
    await page.screenshot({ path: join(shots, "console_tablet.png") });

    const cdp = await tablet.newCDPSession(page);
    const cx = view.x + view.width / 2, cy = view.y + view.height / 2;
    // One finger 80 px to the right turns the camera about the tissue by
    // 2π·80 px / the view's height, the other way (OrbitControls' rule).
    const before = await orbit(page);
    await touchGesture(cdp, [[[cx - 40, cy], [cx + 40, cy]]]);
    const turned = await orbit(page);
    const expected = (-2 * Math.PI * 80) / before.height;
    const turn = Math.atan2(Math.sin(turned.azimuth - before.azimuth), Math.cos(turned.azimuth - before.azimuth));
    assert.ok(Math.abs(turn - expected) < 0.01 * Math.abs(expected),
      `turned ${turn.toFixed(4)} rad, expected ${expected.toFixed(4)}`);
    assert.ok(Math.abs(turned.distance / before.distance - 1) < 1e-6, "turning keeps the distance");
    // Two fingers spreading from 80 to 240 px apart bring the camera 3x closer.
    await touchGesture(cdp, [[[cx - 40, cy], [cx - 120, cy]], [[cx + 40, cy], [cx + 120, cy]]]);
    const zoomed = await orbit(page);
    assert.ok(Math.abs(zoomed.distance / turned.distance - 1 / 3) < 0.01,
      `distance ${turned.distance.toFixed(4)} -> ${zoomed.distance.toFixed(4)} m (expected a third)`);
    assert.deepEqual(errors, []);
  } finally {
    await tablet.close();
  }
});

test("an observer's reset is refused in the page and at the server", async () => {
  const page = await login("observer");
  await page.waitForSelector(`.tile[data-session="${sessions[1]}"]`);
  await page.click(`.tile[data-session="${sessions[1]}"]`);
  assert.equal(await page.isDisabled("#controls button[data-action=reset]"), true, "the page offers no reset");
  // Past the page: the call itself, as a modified page would send it.
  const reply = await page.evaluate(() => window.hapsim.control("reset"));
  assert.equal(reply.code, 7, "PERMISSION_DENIED from the server's access policy");
  assert.match(await page.textContent("#message"), /reset refused/);
  await page.close();
});

const tilePaused = (page, id) => page.$eval(`.tile[data-session="${id}"] .paused`, (e) => !e.hidden);
const tileSimTime = (page, id) =>
  page.$eval(`.tile[data-session="${id}"]`, (e) => Number(e.dataset.simTime || 0));

test("the instructor pauses and resumes a trainee from the page", async () => {
  const page = await login("instructor");
  const id = sessions[1];
  await page.waitForSelector(`.tile[data-session="${id}"]`);
  await page.click(`.tile[data-session="${id}"]`);
  await page.click("#controls button[data-action=pause]");
  await page.waitForFunction(() => /pause: done/.test(document.querySelector("#message").textContent));
  // The server's own class status says paused, and its simulated time stands still.
  await page.waitForFunction((s) => !document.querySelector(`.tile[data-session="${s}"] .paused`).hidden, id);
  await page.waitForTimeout(200);
  const pausedAt = await tileSimTime(page, id);
  const ticksAt = await tileTicks(page, id);
  await page.waitForTimeout(600);
  assert.ok((await tileTicks(page, id)) > ticksAt, "the tiles still update");
  assert.equal(await tileSimTime(page, id), pausedAt, "a paused session's time stands still");
  await page.click("#controls button[data-action=resume]");
  await page.waitForFunction(() => /resume: done/.test(document.querySelector("#message").textContent));
  await page.waitForFunction(([s, at]) => {
    const t = document.querySelector(`.tile[data-session="${s}"]`);
    return t.querySelector(".paused").hidden && Number(t.dataset.simTime) > at;
  }, [id, pausedAt], { timeout: 10000 });
  assert.equal(await tilePaused(page, id), false);
  assert.deepEqual(page.errors, []);
  await page.close();
});

test("the trials table lists the class's trials and downloads as the server's CSV", async () => {
  const page = await login("instructor");
  await page.waitForSelector(`.tile[data-session="${sessions[0]}"]`);
  await page.click("#trials");
  await page.waitForSelector("#trials-panel:not([hidden]) #trials-table tr[data-session]");
  const header = await page.$$eval("#trials-table th", (th) => th.map((e) => e.textContent));
  assert.deepEqual(header.slice(0, 4), ["session", "trainee", "scene", "trial"]);
  const rows = await page.$$eval("#trials-table tr[data-session]", (tr) => tr.map((e) => e.dataset.session));
  for (const id of sessions) assert.ok(rows.includes(id), `a trial row for ${id} (rows: ${rows})`);
  assert.match(await page.textContent("#message"), new RegExp(`^${rows.length} trials$`));
  await page.screenshot({ path: join(shots, "console_trials.png") });
  const [download] = await Promise.all([page.waitForEvent("download"), page.click("#trials-csv")]);
  const csv = readFileSync(await download.path(), "utf8");
  const lines = csv.trim().split("\n");
  assert.equal(lines.length, rows.length + 1, "one CSV line per table row, plus the header");
  assert.ok(lines[0].startsWith("session,trainee,scene,trial,"));
  assert.deepEqual(page.errors, []);
  await page.close();
});

test("the instructor pushes a scenario to the class; an observer cannot", async () => {
  const observer = await login("observer");
  await observer.waitForSelector(`.tile[data-session="${sessions[0]}"]`);
  assert.equal(await observer.isDisabled("#push"), true, "the page offers an observer no push");
  const refused = await observer.evaluate(() =>
    window.hapsim.connection.call("pushScenario", { className: "web-101", scene: "tissue_block", params: {} }));
  assert.equal(refused.code, 7, "PERMISSION_DENIED from the server's access policy");
  await observer.close();

  const page = await login("instructor");
  await page.waitForSelector(`.tile[data-session="${sessions[0]}"]`);
  await page.fill("#push-scene", "tissue_block");
  await page.click("#push");
  await page.waitForFunction(() => /scenario tissue_block pushed/.test(document.querySelector("#message").textContent),
    null, { timeout: 20000 });
  // Every trainee's session is rebuilt with the pushed scene: the tiles say so.
  await page.waitForFunction((ids) => ids.every((s) =>
    document.querySelector(`.tile[data-session="${s}"] .scene`).textContent === "tissue_block"), sessions,
    { timeout: 10000 });
  assert.deepEqual(page.errors, []);
  await page.close();
});

test("the page reconnects after a server restart", async () => {
  const page = await login("instructor");
  const tile = `.tile[data-session="${sessions[0]}"]`;
  await page.waitForSelector(tile);
  await page.waitForFunction(() => document.querySelector("#link-state").dataset.state === "open");
  await page.waitForTimeout(500);
  const ticksBefore = await tileTicks(page, sessions[0]);
  const ticksReadAtMs = Date.now();
  const welcomesBefore = await page.evaluate(() => window.hapsim.connection.welcomes);
  // The restart runs beside this test, which watches the page meanwhile: the
  // link is lost, and the tiles dim the figures they have.
  const restarted = execFileAsync("bash", ["-c", process.env.HAPSIM_RESTART]);
  await page.waitForFunction((t) => document.querySelector("#link-state").dataset.state === "lost" &&
    document.querySelector(t).dataset.stale === "true", tile, { timeout: 10000 });
  await restarted;
  await page.waitForFunction((before) => window.hapsim.connection.welcomes > before &&
    document.querySelector("#link-state").dataset.state === "open", welcomesBefore, { timeout: 20000 });
  // The restarted server's sessions start again from tick 0: the tile follows
  // them, below what the old session (1 tick per ms) would have reached by now.
  await page.waitForFunction(([t, before, readAtMs]) => {
    const e = document.querySelector(t);
    const ticks = Number(e.dataset.ticks);
    return e.dataset.stale === "false" && ticks > 0 && ticks < before + (Date.now() - readAtMs);
  }, [tile, ticksBefore, ticksReadAtMs], { timeout: 10000 });
  await page.close();
});
