// The class console in Firefox (Debian's firefox-esr, driven by puppeteer-core
// over WebDriver BiDi), against the same server, class and load as
// console.test.mjs (tests/integration/web_console.sh runs both, this one
// after). Firefox runs with a window on a virtual X display (DISPLAY, Xvfb):
// its headless mode here has no WebGL, a window gets Mesa's llvmpipe.
// Firefox accepts the server's self-signed certificate (acceptInsecureCerts:
// the connection is TLS all the same; Chromium's test pins the exact key).
//   HAPSIM_WEB_URL, HAPSIM_TOKENS, HAPSIM_SESSIONS, HAPSIM_SHOTS: as for console.test.mjs
//   HAPSIM_FIREFOX        the browser [/usr/bin/firefox-esr]
import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { join } from "node:path";
import puppeteer from "puppeteer-core";
import { assertViewShowsTissueAndNeedle, plotInk, sampleView, sessions, shots, token, url } from "./page_checks.mjs";

let browser;

before(async () => {
  browser = await puppeteer.launch({
    browser: "firefox",
    executablePath: process.env.HAPSIM_FIREFOX || "/usr/bin/firefox-esr",
    headless: false,
    // The window's size, not an emulated viewport: Firefox ESR 140 (Debian 12
    // without its security updates) lacks the BiDi command puppeteer's
    // setViewport sends.
    defaultViewport: null,
    args: ["--width=1366", "--height=768"],
    acceptInsecureCerts: true,
    extraPrefsFirefox: { "webgl.force-enabled": true },  // Mesa's software GL is on Firefox's blocklist
    timeout: 60000,
    protocolTimeout: 30000,
  });
});
after(async () => browser && (await browser.close()));

async function login(who) {
  const page = await browser.newPage();
  page.errors = [];
  page.on("pageerror", (e) => page.errors.push(e.message));
  const response = await page.goto(url);
  assert.equal(response.status(), 200);
  assert.ok(page.url().startsWith("https://"), "served over TLS");
  await page.type("#token", who === "garbage" ? "garbage-token" : token(who));
  await page.click("#login button[type=submit]");
  return page;
}

// Polls fn(...args) in the page until it is true. (puppeteer's own
// waitForFunction builds a Function in the page, which Firefox ESR 140
// refuses under the console's Content-Security-Policy.)
async function until(page, fn, { timeout = 5000 } = {}, ...args) {
  const end = Date.now() + timeout;
  while (!(await page.evaluate(fn, ...args))) {
    if (Date.now() > end) throw new Error(`timed out after ${timeout} ms waiting for ${fn}`);
    await new Promise((r) => setTimeout(r, 50));
  }
}

const tileTicks = (page, id) => page.$eval(`.tile[data-session="${id}"]`, (e) => Number(e.dataset.ticks || 0));
const message = (page) => page.$eval("#message", (e) => e.textContent);

test("in Firefox: a garbage token is refused and the page says so", async () => {
  const page = await login("garbage");
  await until(page, () => document.querySelector("#login-error").textContent.includes("Refused"));
  assert.match(await page.$eval("#login-error", (e) => e.textContent), /unknown token/);
  await page.close();
});

test("in Firefox: the tiles update, a trainee's view draws the needle where its pose projects, and the controls work",
  async () => {
    const page = await login("instructor");
    for (const id of sessions) {
      await until(page, (s) => document.querySelector(`.tile[data-session="${s}"]`) !== null, { timeout: 10000 }, id);
    }
    const first = await tileTicks(page, sessions[0]);
    await until(page, (id, at) => Number(document.querySelector(`.tile[data-session="${id}"]`).dataset.ticks) > at,
      { timeout: 5000 }, sessions[0], first);

    await page.click(`.tile[data-session="${sessions[0]}"]`);
    await until(page, () => window.hapsim.view && window.hapsim.view.projectedTip() !== null &&
      window.hapsim.framesApplied > 30, { timeout: 10000 });
    assertViewShowsTissueAndNeedle(await page.evaluate(sampleView));
    await new Promise((r) => setTimeout(r, 300));  // plots are drawn at 10 Hz
    const ink = await page.evaluate(plotInk);
    assert.ok(ink > 200, `the force-time plot is drawn (${ink} pixels)`);
    await page.screenshot({ path: join(shots, "console_firefox.png") });

    await page.click("#controls button[data-action=pause]");
    await until(page, () => /pause: done/.test(document.querySelector("#message").textContent));
    await until(page, (id) => !document.querySelector(`.tile[data-session="${id}"] .paused`).hidden,
      {}, sessions[0]);
    await page.click("#controls button[data-action=resume]");
    await until(page, () => /resume: done/.test(document.querySelector("#message").textContent));

    await page.click("#trials");
    await until(page, () => document.querySelector("#trials-panel:not([hidden]) #trials-table tr[data-session]") !== null);
    const rows = await page.$$eval("#trials-table tr[data-session]", (tr) => tr.map((e) => e.dataset.session));
    for (const id of sessions) assert.ok(rows.includes(id), `a trial row for ${id} (rows: ${rows})`);
    assert.match(await message(page), new RegExp(`^${rows.length} trials$`));
    assert.deepEqual(page.errors, []);
    await page.close();
  });
