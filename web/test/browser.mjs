// browser.mjs URL [SCREENSHOT.png] - headless Chromium (Debian's, through
// playwright-core) opens the dashboard served by a live wgweb: waits for
// data, checks every plot holds samples (data-samples), ramps omega with the
// ramp control and then sets omega = 1.2 with the set control, checks the
// daemon's PARAMS (as the page received it) show 1.2, and keeps a
// screenshot. Then, with the daemon paused (SIGSTOP), a hostile sender
// (WG_SPOOF: tests/clients/wgspoof) publishes on the daemon's channels for
// 6 s: angles that are NaN, +-inf, 1e308, negative, 2 pi and beyond; the
// status table may show only "–" or the one valid pair it sends (1.5 rad,
// 3.0 rad = 85.94°, 171.89°), and its STATUS strings' markup (an <img>
// whose onerror would set window.wgPwned, a <b id=wgpwn>) only as text;
// its PARAMS (no daemon sends them: a NaN scale, N = 0) never reach the
// page, whose caption stays the daemon's. Prints "ok ..." lines; exit 0 on
// success, 1 on a failure.
import { chromium } from "playwright-core";
import { spawn } from "node:child_process";
import assert from "node:assert/strict";

const url = process.argv[2].replace(/^ws/, "http");
const shot = process.argv[3] ?? `${process.env.WG_OUT ?? "."}/dashboard.png`;
const exe = process.env.CHROMIUM ?? "/usr/bin/chromium";
const browser = await chromium.launch({
  executablePath: exe,
  args: ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync"],
});
let status = 0;
try {
  const page = await browser.newPage({ viewport: { width: 1400, height: 1250 } });
  const errors = [];
  page.on("pageerror", (e) => errors.push(String(e)));
  page.on("console", (m) => m.type() === "error" && errors.push(m.text()));
  await page.goto(url);
  // every text the x_n caption takes, from the first (it began "; samples …"
  // while no PARAMS had come)
  await page.evaluate(() => {
    const el = document.querySelector("#cap-xn");
    window.capTexts = [el.textContent];
    new MutationObserver(() => window.capTexts.push(el.textContent))
      .observe(el, { childList: true, characterData: true, subtree: true });
  });
  const samples = (id) => page.$eval(id, (el) => +el.dataset.samples);
  await page.waitForFunction(() => window.wgTest?.params && window.wgTest.scope > 50 && window.wgTest.poincare > 20,
    null, { timeout: 15000 });
  for (const id of ["#plot-xn", "#plot-f", "#plot-phase", "#plot-poincare"])
    await page.waitForFunction((s) => +document.querySelector(s).dataset.samples > 0, id, { timeout: 5000 });
  console.log(`ok data: x_n ${await samples("#plot-xn")} samples, poincare ${await samples("#plot-poincare")} points`);
  await page.waitForFunction(() => /worm θ1, wheel θ2\s*\d+\.\d\d°, \d+\.\d\d°/.test(document.querySelector("#status").textContent),
    null, { timeout: 5000 });
  console.log(`ok angles shown: ${(await page.textContent("#status")).match(/worm θ1, wheel θ2\s*[^a-z]*/)[0].trim()}`);

  // Ramp omega 0.5 -> 1.6 with the ramp control (first jump to 0.5 with set).
  await page.selectOption("#set-name", "omega");
  await page.fill("#set-value", "0.5");
  await page.click("#set-btn");
  await page.waitForFunction(() => window.wgTest.params.values.omega === 0.5, null, { timeout: 5000 });
  await page.selectOption("#ramp-name", "omega");
  await page.fill("#ramp-to", "1.6");
  await page.fill("#ramp-dur", process.env.RAMP_S ?? "3");
  await page.click("#ramp-btn");
  await page.waitForFunction(() => window.wgTest.acks.some((a) => a.op === "ramp" && a.accepted), null, { timeout: 5000 });
  // The ramp lasts 3 s of simulated time: at the daemon's real-time factor
  // (a sanitizer build on a busy host: 0.1 and less) that is 30 s of wall
  // time and more. So the wait is in simulated time: the ramp must end
  // within 2 s of it past its length, however long that takes here.
  const ramp0 = await page.evaluate(() => window.wgTest.status.t_s);
  const rampLen = +(process.env.RAMP_S ?? "3");
  await page.waitForFunction((end) => window.wgTest.params.reason === "ramp-end" || window.wgTest.params.values.omega >= 1.6 ||
    (window.wgTest.status?.t_s ?? -Infinity) > end, ramp0 + rampLen + 2, { timeout: 150000 });
  assert.ok(await page.evaluate(() => window.wgTest.params.reason === "ramp-end" || window.wgTest.params.values.omega >= 1.6),
    "the ramp ended within 2 s of simulated time past its length");
  const bif = await samples("#plot-bif");
  assert.ok(bif > 200, `bifurcation diagram holds ${bif} points`);
  console.log(`ok ramp: bifurcation diagram ${bif} points`);

  // Set omega = 1.2 with the control; the daemon's PARAMS must show it.
  await page.fill("#set-value", "1.2");
  await page.click("#set-btn");
  await page.waitForFunction(() => window.wgTest.params.values.omega === 1.2, null, { timeout: 5000 });
  await page.waitForFunction(() => /omega.*OK|set: OK/.test(document.querySelector("#cmd-result").textContent), null, { timeout: 5000 });
  console.log(`ok set: daemon PARAMS omega = 1.2, result line "${await page.textContent("#cmd-result")}"`);
  await page.waitForTimeout(+(process.env.SETTLE_MS ?? 2500));
  await page.screenshot({ path: shot, fullPage: true });
  console.log(`ok screenshot ${shot}`);

  const caps = await page.evaluate(() => window.capTexts);
  assert.ok(caps.length > 1 && caps.every((t) => !/^\s*;/.test(t)),
    `the x_n caption never starts with "; ": ${JSON.stringify(caps.filter((t) => /^\s*;/.test(t)).slice(0, 2))}`);
  console.log(`ok x_n caption: ${caps.length} texts, none starting with "; "`);
  if (process.env.WG_SPOOF) await spoofed(page);
  assert.deepEqual(errors, [], "no page errors");
} catch (e) {
  console.log("FAIL", e.message);
  status = 1;
} finally {
  await browser.close();
}
process.exit(status);

// The hostile sender's phase (see the top): every θ text shown while only
// wgspoof publishes must be "–" or its one valid pair.
async function spoofed(page) {
  const env = process.env, pid = +env.WG_DAEMON_PID;
  const thetaText = () => page.$eval("#status", (el) => {
    const row = [...el.querySelectorAll("tr")].find((tr) => tr.cells[0].textContent.startsWith("worm θ1"));
    return row ? row.cells[1].textContent : null;
  });
  process.kill(pid, "SIGSTOP");
  const spoof = spawn(env.WG_SPOOF, [env.WORMGEAR_URL, env.WORMGEAR_PREFIX, "6", "params"], { stdio: "inherit" });
  const exited = new Promise((r) => spoof.on("exit", (code) => r(code)));
  try {
    const n0 = await page.evaluate(() => window.wgTest.scope);
    await page.waitForFunction((n) => window.wgTest.scope > n + 20, n0, { timeout: 4000 });
    await page.waitForTimeout(300); // the status table is redrawn every 250 ms
    const shown = new Map();
    for (let i = 0; i < 80; i++) {
      const t = await thetaText();
      shown.set(t, (shown.get(t) ?? 0) + 1);
      await page.waitForTimeout(25);
    }
    const markup = await page.evaluate(() => ({
      pwned: window.wgPwned, injected: document.getElementById("wgpwn") !== null,
      shownAsText: document.querySelector("#status").textContent.includes("<b id=wgpwn>P9</b>"),
      // STATUS tick_refusal (a tick's only answer) shown in its row, as text
      tickAsText: document.querySelector("#status").textContent.includes("3 — the last: <img src=x onerror"),
      img: document.querySelectorAll("#status img").length,
      // STATUS drops told apart: publish failures and ticks lost
      drops: document.querySelector("#status").textContent.includes("daemon not published 5, ticks lost 7,"),
    }));
    const caption = await page.textContent("#caption");
    const code = await exited;
    const bad = [...shown.keys()].filter((t) => t !== "–" && t !== "85.94°, 171.89°");
    const rejected = await page.evaluate(() => window.wgTest.badAngles);
    console.log(`ok? spoofed: shown ${JSON.stringify([...shown])}; ${rejected} samples refused; wgspoof exit ${code}`);
    assert.equal(code, 0, "wgspoof ran");
    assert.ok(rejected > 0, "the page saw wgspoof's angles");
    assert.deepEqual(bad, [], "only angles in [0, 360)° are shown");
    console.log(`ok? markup in STATUS strings: ${JSON.stringify(markup)}`);
    assert.deepEqual(markup, { pwned: undefined, injected: false, shownAsText: true, tickAsText: true, img: 0, drops: true },
      "STATUS strings shown as text, never run as markup");
    console.log("ok spoofed: no angle that is not an angle was shown");
    assert.ok(/^scene table3 /.test(caption) && !/passwd|NaN/.test(caption),
      `the caption is still the daemon's PARAMS: "${caption}"`);
    console.log(`ok spoofed PARAMS (NaN scale, N = 0, unknown model) not forwarded: "${caption.slice(0, 60)}…"`);
    const shot2 = `${env.WG_OUT ?? "."}/dashboard-spoofed.png`;
    await page.screenshot({ path: shot2, fullPage: true });
    console.log(`ok screenshot under the hostile sender ${shot2}`);
  } finally {
    spoof.kill("SIGKILL");
    process.kill(pid, "SIGCONT");
  }
}
