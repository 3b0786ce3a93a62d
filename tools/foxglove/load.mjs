// Foxglove's load of a wetbounce MCAP (issue 30, item 3), measured in headless Chromium on a
// web build of Lichtblick, the open-source fork of Foxglove Studio that keeps its MCAP reader
// and 3D panel (docs/output.md, "Why spheres, at every count", has the numbers and how they
// were made). Not part of CI. Set-up, once:
//
//   - a Lichtblick web build (github.com/lichtblick-suite/lichtblick: `yarn install`,
//     `yarn web:build:prod`; 1.28.1 was measured), served with its data folder by
//     `node tools/foxglove/serve.mjs 8080 LICHTBLICK/web/.webpack DATA_DIR &`;
//   - `apt-get install chromium`, and `npm install playwright-core@1 @mcap/core@2` in this folder.
//
//   node tools/foxglove/load.mjs FILE.mcap [LAYOUT.json] [options]
//
// Options:
//   --mode=file|url   file (default): app opened at /, file given to the app's hidden
//                     <input data-puppeteer-file-upload> with Playwright setInputFiles (like "Open local file").
//                     url: app opened at /?ds=remote-file&ds.url=http://127.0.0.1:PORT/data/<basename>
//                     (FILE must then be inside the server's data folder).
//   --port=8080       port of serve.mjs
//   --secs=10         playback measurement window (s)
//   --speed=1         playback speed (sets layout playbackConfig.speed when the layout is generated)
//   --shot=out/foxglove_load.png   screenshot of the 3-D panel after the first data frame
//   --page-shot=PATH  screenshot of the whole window after playback
//   --timeout=180     max seconds to wait for ready / first data frame
//   --width=1280 --height=800        browser viewport
//   --debug           print progress to stderr
//
// Without LAYOUT.json a layout with a single 3-D panel is generated in which every
// foxglove.SceneUpdate / foxglove.PointCloud (and other foxglove.* 3-D) topic of the file is visible.
// A given LAYOUT.json is imported as-is (Layouts tab -> "Import from file…").
import fs from "node:fs";
import path from "node:path";
import { chromium } from "playwright-core";
import { McapIndexedReader } from "@mcap/core";

const argv = process.argv.slice(2);
const opts = Object.fromEntries(argv.filter((a) => a.startsWith("--")).map((a) => {
  const [k, v] = a.slice(2).split("="); return [k, v ?? true];
}));
const pos = argv.filter((a) => !a.startsWith("--"));
if (pos.length < 1) { console.error("usage: node measure.mjs FILE.mcap [LAYOUT.json] [--mode=file|url] [--secs=10] ..."); process.exit(2); }
const FILE = path.resolve(pos[0]);
const LAYOUT = pos[1] ? path.resolve(pos[1]) : undefined;
const MODE = opts.mode ?? "file";
const PORT = Number(opts.port ?? 8080);
const SECS = Number(opts.secs ?? 10);
const SPEED = Number(opts.speed ?? 1);
const SHOT = opts.shot ?? "out/foxglove_load.png";
const TIMEOUT = Number(opts.timeout ?? 180) * 1000;
const DEBUG = !!opts.debug;
const BASE = `http://127.0.0.1:${PORT}/`;
const log = (...a) => { if (DEBUG) console.error(`[${(performance.now() / 1000).toFixed(1)}s]`, ...a); };

// ---------- read the MCAP summary (topics) to build a default layout ----------
async function readTopics(file) {
  const fh = await fs.promises.open(file, "r");
  try {
    const size = BigInt((await fh.stat()).size);
    const readable = { size: async () => size, read: async (offset, len) => {
      const buf = new Uint8Array(Number(len)); await fh.read(buf, 0, Number(len), Number(offset)); return buf; } };
    const reader = await McapIndexedReader.Initialize({ readable });
    const out = [];
    for (const ch of reader.channelsById.values()) {
      const schema = reader.schemasById.get(ch.schemaId);
      const st = reader.statistics?.channelMessageCounts.get(ch.id);
      out.push({ topic: ch.topic, schema: schema?.name ?? "", encoding: ch.messageEncoding, messages: st != null ? Number(st) : undefined });
    }
    const s = reader.statistics;
    return { topics: out, durationS: s ? Number(s.messageEndTime - s.messageStartTime) / 1e9 : undefined,
      messages: s ? Number(s.messageCount) : undefined };
  } finally { await fh.close(); }
}

function makeLayout(topics) {
  const vis = {};
  for (const t of topics) if (/^foxglove[._]|^visualization_msgs|^sensor_msgs\/(msg\/)?PointCloud2/.test(t.schema)) vis[t.topic] = { visible: true };
  return {
    configById: {
      "3D!fgmeasure": {
        cameraState: { perspective: true, distance: 20, phi: 60, thetaOffset: 45, targetOffset: [0, 0, 0],
          target: [0, 0, 0], targetOrientation: [0, 0, 0, 1], fovy: 45, near: 0.5, far: 5000 },
        followMode: "follow-pose", scene: {}, transforms: {}, topics: vis, layers: {
          grid: { visible: true, frameLocked: true, label: "Grid", instanceId: "grid", layerId: "foxglove.Grid",
            size: 10, divisions: 10, lineWidth: 1, color: "#248eff", position: [0, 0, 0], rotation: [0, 0, 0], order: 1 } },
        publish: { type: "point", poseTopic: "/move_base_simple/goal", pointTopic: "/clicked_point",
          poseEstimateTopic: "/initialpose", poseEstimateXDeviation: 0.5, poseEstimateYDeviation: 0.5, poseEstimateThetaDeviation: 0.26179939 },
        imageMode: {},
      },
    },
    globalVariables: {}, userNodes: {}, playbackConfig: { speed: SPEED }, layout: "3D!fgmeasure",
  };
}

// ---------- in-page instrumentation (runs before app code on every navigation) ----------
const INIT = () => {
  const S = (window.__fgm = { sigOn: true, batches: [], firstDataT: null, firstDataBatch: null, cur: null,
    raf: [], rafOn: false, contexts: 0 });
  const flush = () => {
    const c = S.cur; S.cur = null; c.tEnd = performance.now();
    if (S.firstDataT == null && c.dataDraws > 0) {
      S.firstDataT = c.tEnd; S.firstDataBatch = c; const gl = c.gl;
      // force the GPU (SwiftShader) to finish this frame: 1-pixel readPixels = sync point
      try { gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4)); } catch {}
      S.firstDataRasterT = performance.now();
      // next-next animation frame ~ the frame has been composited/presented
      requestAnimationFrame(() => requestAnimationFrame(() => { S.firstDataPresentT = performance.now(); }));
    }
    c.gl = null;
    S.batches.push(c); if (S.batches.length > 20000) S.batches.splice(0, 10000);
  };
  const rec = (gl, mode, count, instances) => {
    let c = S.cur;
    if (!c) { c = S.cur = { gl, t: performance.now(), draws: 0, dataDraws: 0, instDraws: 0, instances: 0, points: 0, prims: 0, sig: [] }; queueMicrotask(flush); }
    c.draws++;
    // "data" draw = GL_POINTS draw (point clouds) or an instanced draw that is not a fat-line
    // segment (three.js LineSegments2 = 18 indices/instance, used by the grid layer and line markers)
    let data = mode === 0;
    // (instanceCount 3 = the x/y/z axes drawn for each coordinate frame: also ignored)
    if (instances != null) { c.instDraws++; if (count !== 18 && instances !== 3 && instances > 0) { c.instances += instances; data = true; } }
    if (mode === 0) c.points += count * (instances ?? 1);
    if (data) c.dataDraws++;
    c.prims += count * (instances ?? 1);
    if (S.sigOn && c.sig.length < 20) c.sig.push([mode, count, instances ?? null]);
  };
  for (const Ctx of [window.WebGL2RenderingContext, window.WebGLRenderingContext]) {
    if (!Ctx) continue;
    const p = Ctx.prototype;
    const wrap = (name, fn) => { const orig = p[name]; if (!orig) return; p[name] = function (...a) { fn(this, a); return orig.apply(this, a); }; };
    wrap("drawArrays", (g, a) => rec(g, a[0], a[2]));
    wrap("drawElements", (g, a) => rec(g, a[0], a[1]));
    wrap("drawRangeElements", (g, a) => rec(g, a[0], a[3]));
    wrap("drawArraysInstanced", (g, a) => rec(g, a[0], a[2], a[3]));
    wrap("drawElementsInstanced", (g, a) => rec(g, a[0], a[1], a[4]));
  }
  const gc = HTMLCanvasElement.prototype.getContext;
  HTMLCanvasElement.prototype.getContext = function (type, ...rest) {
    const ctx = gc.call(this, type, ...rest);
    if (ctx && /webgl/.test(type) && !this.__fgmCounted) { this.__fgmCounted = true; S.contexts++; }
    return ctx;
  };
  const loop = (t) => { if (S.rafOn) S.raf.push(t); requestAnimationFrame(loop); };
  requestAnimationFrame(loop);
};

// ---------- helpers ----------
function chromiumRssMB() {
  // sum RSS of all processes descending from this node process (= the browser)
  const kids = new Map();
  for (const d of fs.readdirSync("/proc")) {
    if (!/^\d+$/.test(d)) continue;
    try { const st = fs.readFileSync(`/proc/${d}/stat`, "utf8"); const ppid = Number(st.slice(st.lastIndexOf(")") + 2).split(" ")[1]);
      if (!kids.has(ppid)) kids.set(ppid, []); kids.get(ppid).push(Number(d)); } catch {}
  }
  let kb = 0; const stack = [...(kids.get(process.pid) ?? [])];
  while (stack.length) { const p = stack.pop(); stack.push(...(kids.get(p) ?? []));
    try { const m = /VmRSS:\s+(\d+)/.exec(fs.readFileSync(`/proc/${p}/status`, "utf8")); if (m) kb += Number(m[1]); } catch {} }
  return Math.round(kb / 1024);
}
const heap = (page) => page.evaluate(() => performance.memory ? {
  usedJSHeapMB: +(performance.memory.usedJSHeapSize / 2 ** 20).toFixed(1),
  totalJSHeapMB: +(performance.memory.totalJSHeapSize / 2 ** 20).toFixed(1) } : null);
const pctl = (arr, p) => { if (!arr.length) return null; const s = [...arr].sort((a, b) => a - b); return s[Math.min(s.length - 1, Math.floor(p * s.length))]; };
const r1 = (x) => (x == null ? null : Math.round(x * 10) / 10);

async function closeDialog(page) {
  const dlg = page.getByTestId("DataSourceDialog");
  if (await dlg.isVisible().catch(() => false)) {
    await dlg.getByTestId("CloseIcon").click({ timeout: 5000 }).catch(() => page.keyboard.press("Escape"));
  }
}

// ---------- main ----------
const result = { file: FILE, sizeMB: +(fs.statSync(FILE).size / 2 ** 20).toFixed(2), mode: MODE, layout: LAYOUT ?? "generated" };
let summary;
try { summary = await readTopics(FILE); result.topics = summary.topics; result.fileDurationS = summary.durationS; }
catch (e) { result.summaryError = String(e); summary = { topics: [] }; }
const layoutJson = LAYOUT ? fs.readFileSync(LAYOUT, "utf8") : JSON.stringify(makeLayout(summary.topics));
const layoutName = LAYOUT ? path.basename(LAYOUT) : "fgmeasure-3d.json";

if (MODE === "url") {
  const u = `${BASE}data/${path.basename(FILE)}`;
  const r = await fetch(u, { method: "HEAD" }).catch((e) => ({ ok: false, status: String(e) }));
  if (!r.ok) { console.error(`--mode=url: ${u} not served (${r.status}); put the file in the server's data dir`); process.exit(3); }
}
const browser = await chromium.launch({
  executablePath: "/usr/bin/chromium", headless: true,
  args: ["--headless", "--no-sandbox", "--disable-quic", "--no-first-run", "--disable-background-networking",
    "--disable-component-update", "--disable-sync", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
    "--ignore-gpu-blocklist", "--enable-precise-memory-info", "--js-flags=--expose-gc"],
});
try {
  const ctx = await browser.newContext({ viewport: { width: Number(opts.width ?? 1280), height: Number(opts.height ?? 800) } });
  await ctx.addInitScript(INIT);
  const page = await ctx.newPage();
  const errors = [];
  page.on("pageerror", (e) => errors.push(String(e).slice(0, 300)));
  page.on("console", (m) => { if (m.type() === "error") errors.push(m.text().slice(0, 300)); if (DEBUG && m.type() === "error") log("console.error", m.text().slice(0, 200)); });

  // 1) set-up visit: import the layout (stored in the browser context's IndexedDB, becomes the current layout)
  log("setup: loading app + importing layout", layoutName);
  await page.goto(BASE, { waitUntil: "load" });
  await page.getByTestId("layouts-left").waitFor({ timeout: 60000 });
  await closeDialog(page);
  await page.evaluate(({ text, name }) => {
    window.showOpenFilePicker = async () => [{ kind: "file", name, getFile: async () => new File([text], name, { type: "application/json" }) }];
  }, { text: layoutJson, name: layoutName });
  await page.getByTestId("layouts-left").click();
  await page.getByRole("button", { name: "Import from file…" }).click();
  const lname = layoutName.replace(/\.json$/, "");
  await page.getByTestId("layout-list-item").getByText(lname, { exact: true }).first().waitFor({ timeout: 15000 });
  await page.getByTestId("layout-list-item").getByText(lname, { exact: true }).first().click();
  await page.getByTestId("left-sidebar-button").click().catch(() => {}); // hide the sidebar: 3-D panel gets the full width
  await page.waitForTimeout(1500); // let the layout selection + sidebar state persist

  // 2) timed visit
  const url = MODE === "url"
    ? `${BASE}?ds=remote-file&ds.url=${encodeURIComponent(`${BASE}data/${path.basename(FILE)}`)}`
    : BASE;
  log("timed run:", url);
  await page.goto(url, { waitUntil: "commit" });
  if (MODE === "file") {
    const input = page.locator("[data-puppeteer-file-upload]");
    await input.waitFor({ state: "attached", timeout: 60000 });
    result.appBootMs = r1(await page.evaluate(() => performance.now()));
    await input.setInputFiles(FILE);
    result.fileSelectedMs = r1(await page.evaluate(() => performance.now()));
    log("file selected");
  }
  // ready: play button enabled and no loading indicator
  await page.waitForFunction(() => {
    const b = document.querySelector('[data-testid="play-button"]');
    if (!b || b.disabled || b.getAttribute("aria-disabled") === "true") return false;
    if (document.querySelector('[data-testid="progress-plot"]')) return false;
    return (window.__fgm.readyT = performance.now());
  }, null, { timeout: TIMEOUT, polling: 20 });
  result.readyMs = r1(await page.evaluate(() => window.__fgm.readyT));
  log("ready", result.readyMs);
  await closeDialog(page);
  // first 3-D frame with data (instanced draw or GL_POINTS draw)
  const first = await page.waitForFunction(() => window.__fgm.firstDataPresentT, null, { timeout: TIMEOUT, polling: 20 })
    .then(() => page.evaluate(() => ({ t: window.__fgm.firstDataT, tr: window.__fgm.firstDataRasterT, tp: window.__fgm.firstDataPresentT, b: window.__fgm.firstDataBatch })))
    .catch(() => null);
  result.firstDataFrameMs = first ? r1(first.t) : null;            // GL draw calls for the first frame with data issued
  result.firstDataFrameRasterizedMs = first ? r1(first.tr) : null; // ... and finished by the GPU (readPixels sync)
  result.firstDataFramePresentedMs = first ? r1(first.tp) : null;  // ... and 2 animation frames later (on screen)
  if (first) result.firstDataBatch = { draws: first.b.draws, dataDraws: first.b.dataDraws, instances: first.b.instances, points: first.b.points, primitives: first.b.prims };
  else result.firstDataFrameError = "no instanced/points draw call seen in 3-D panel within timeout";
  log("first data frame", result.firstDataFrameMs);
  if (DEBUG) log("GL batches until first data frame [t, [[mode,count,instances]...]]:", JSON.stringify(await page.evaluate(() => window.__fgm.batches.slice(0, 40).map((b) => [Math.round(b.t), b.sig]))));
  await page.evaluate(() => { window.__fgm.sigOn = false; });
  await page.waitForTimeout(500);
  result.heapAfterLoad = await heap(page);
  result.chromiumRssMBAfterLoad = chromiumRssMB();
  // screenshot of the 3-D panel (largest canvas)
  const canvasBox = await page.evaluate(() => {
    let best = null;
    for (const c of document.querySelectorAll("canvas")) { const r = c.getBoundingClientRect(); if (!best || r.width * r.height > best.width * best.height) best = { x: r.x, y: r.y, width: r.width, height: r.height }; }
    return best;
  });
  if (canvasBox && canvasBox.width > 0) await page.screenshot({ path: SHOT, clip: canvasBox });
  else await page.screenshot({ path: SHOT });
  result.screenshot = SHOT;

  // 3) playback
  const timeText = () => page.getByTestId("PlaybackTime-text").locator("input").inputValue().catch(() => null);
  result.playbackStartTime = await timeText();
  const isPlaying = () => page.evaluate(() => document.querySelector('[data-testid="play-button"]')?.getAttribute("title") === "Pause");
  await page.getByTestId("play-button").click();
  await page.waitForFunction(() => document.querySelector('[data-testid="play-button"]')?.getAttribute("title") === "Pause", null, { timeout: 10000 }).catch(() => {});
  // the whole window is timed inside the page (evaluate calls would stall while the renderer is busy)
  const m = await page.evaluate(async (secs) => {
    const S = window.__fgm; S.raf = []; S.rafOn = true; const mark = S.batches.length;
    const t0 = performance.now(); let endedAt = null;
    const playing = () => document.querySelector('[data-testid="play-button"]')?.getAttribute("title") === "Pause";
    await new Promise((res) => { const iv = setInterval(() => {
      const t = performance.now();
      if (endedAt == null && !playing()) endedAt = t - t0;
      if (t - t0 >= secs * 1000) { clearInterval(iv); res(); } }, 50); });
    S.rafOn = false; const t1 = performance.now();
    const batches = S.batches.slice(mark).filter((b) => b.t >= t0 && b.t <= t1);
    return { wall: t1 - t0, endedAt, raf: S.raf.slice(), batches: batches.map((b) => ({ t: b.t, dur: b.tEnd - b.t, data: b.dataDraws > 0, inst: b.instances, pts: b.points })) };
  }, SECS);
  const endedEarlyAtS = m.endedAt == null ? null : r1(m.endedAt / 1000);
  result.playbackEndTime = await timeText();
  const iv = []; for (let i = 1; i < m.raf.length; i++) iv.push(m.raf[i] - m.raf[i - 1]);
  const dataBatches = m.batches.filter((b) => b.data);
  result.playback = {
    wallS: r1(m.wall / 1000),
    rafFps: r1((m.raf.length - 1) / ((m.raf.at(-1) - m.raf[0]) / 1000)),
    frameMsP50: r1(pctl(iv, 0.5)), frameMsP95: r1(pctl(iv, 0.95)), frameMsMax: r1(Math.max(...iv)),
    longFramesOver50ms: iv.filter((x) => x > 50).length,
    renders3dPerS: r1(dataBatches.length / (m.wall / 1000)),
    allGlBatchesPerS: r1(m.batches.length / (m.wall / 1000)),
    glSubmitMsP50: r1(pctl(dataBatches.map((b) => b.dur), 0.5)),
    lastRenderInstances: dataBatches.at(-1)?.inst ?? null, lastRenderPoints: dataBatches.at(-1)?.pts ?? null,
    endedEarlyAtS,
  };
  const ts0 = Date.parse(result.playbackStartTime ?? ""), ts1 = Date.parse(result.playbackEndTime ?? "");
  if (Number.isFinite(ts0) && Number.isFinite(ts1)) {
    result.playback.dataTimeAdvancedS = r1((ts1 - ts0) / 1000);
    result.playback.realtimeFactor = Math.round(((ts1 - ts0) / m.wall) * 100) / 100; // 1.0 = keeps up at 1x speed
  }
  if (SECS > 0 && await isPlaying()) await page.getByTestId("play-button").click().catch(() => {});
  if (opts["page-shot"]) { await page.screenshot({ path: opts["page-shot"] }); result.pageShot = opts["page-shot"]; }
  result.heapAfterPlayback = await heap(page);
  result.chromiumRssMBAfterPlayback = chromiumRssMB();
  result.webglContexts = await page.evaluate(() => window.__fgm.contexts);
  result.pageErrors = errors.slice(0, 10);
  console.log(JSON.stringify(result, null, 2));
} finally {
  await browser.close();
}
