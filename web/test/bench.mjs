// bench.mjs HTTP_URL SECONDS [SCREENSHOT] - the dashboard in headless
// Chromium for SECONDS against a live wgweb; prints frame-interval and
// publish-to-screen latency figures read from the page's test hook
// (window.wgTest). A benchmark: prints figures, never fails on a time.
import { chromium } from "playwright-core";

const [url, secs = "20", shot] = process.argv.slice(2);
const pct = (a, p) => { const s = [...a].sort((x, y) => x - y); return s[Math.min(s.length - 1, Math.floor(p * s.length))]; };
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
  args: ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run", "--disable-background-networking",
    "--disable-component-update", "--disable-sync"],
});
const page = await browser.newPage({ viewport: { width: 1400, height: 1250 } });
await page.goto(url);
await page.waitForFunction(() => window.wgTest?.scope > 100, null, { timeout: 20000 });
await page.evaluate(() => { window.wgTest.frameIntervals.length = 0; window.wgTest.latencies.length = 0; window.wgTest.work.length = 0; window.wgTest.t0 = performance.now(); window.wgTest.f0 = window.wgTest.frames; window.wgTest.s0 = window.wgTest.scope; });
await page.waitForTimeout(+secs * 1000);
const r = await page.evaluate(() => ({ fi: window.wgTest.frameIntervals.slice(), lat: window.wgTest.latencies.slice(), work: window.wgTest.work.slice(),
  frames: window.wgTest.frames - window.wgTest.f0, scope: window.wgTest.scope - window.wgTest.s0,
  ms: performance.now() - window.wgTest.t0, bif: +document.querySelector("#plot-bif").dataset.samples }));
if (shot) await page.screenshot({ path: shot, fullPage: true });
await browser.close();
const fps = (r.frames * 1000) / r.ms, long = r.fi.filter((x) => x > 1000 / 50).length;
console.log(`dashboard: ${fps.toFixed(1)} frames/s over ${(r.ms / 1000).toFixed(1)} s; frame interval p50 ${pct(r.fi, 0.5).toFixed(1)} ms, p95 ${pct(r.fi, 0.95).toFixed(1)} ms, p99 ${pct(r.fi, 0.99).toFixed(1)} ms, max ${Math.max(...r.fi).toFixed(1)} ms; ${long} of ${r.fi.length} frames over 20 ms`);
console.log(`script time per frame (our JS: plots, status): p50 ${pct(r.work, 0.5).toFixed(2)} ms, p99 ${pct(r.work, 0.99).toFixed(2)} ms, max ${Math.max(...r.work).toFixed(1)} ms`);
console.log(`publish-to-screen latency (daemon STATE utime -> the frame that drew it): p50 ${pct(r.lat, 0.5).toFixed(1)} ms, p95 ${pct(r.lat, 0.95).toFixed(1)} ms, p99 ${pct(r.lat, 0.99).toFixed(1)} ms (${r.lat.length} frames)`);
console.log(`received: ${(r.scope * 1000 / r.ms).toFixed(0)} /scope samples/s; bifurcation diagram ${r.bif} points`);
