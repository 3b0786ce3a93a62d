// Static server for the Lichtblick web build + MCAP files (with HTTP Range support).
// node serve.mjs [PORT] [APP_DIR] [DATA_DIR]
//   /            -> APP_DIR (default LICHTBLICK/web/.webpack)
//   /data/<f>    -> DATA_DIR/<f> (default out/foxglove_size)
import http from "node:http";
import fs from "node:fs";
import path from "node:path";
const PORT = Number(process.argv[2] ?? 8080);
const APP = path.resolve(process.argv[3] ?? "LICHTBLICK/web/.webpack");
const DATA = path.resolve(process.argv[4] ?? "out/foxglove_size");
const MIME = { ".html": "text/html; charset=utf-8", ".js": "text/javascript", ".mjs": "text/javascript",
  ".css": "text/css", ".json": "application/json", ".wasm": "application/wasm", ".png": "image/png",
  ".svg": "image/svg+xml", ".ico": "image/x-icon", ".woff2": "font/woff2", ".woff": "font/woff",
  ".ttf": "font/ttf", ".map": "application/json", ".webmanifest": "application/manifest+json" };
http.createServer((req, res) => {
  const url = new URL(req.url, "http://x");
  let p = decodeURIComponent(url.pathname);
  let root = APP;
  if (p.startsWith("/data/")) { root = DATA; p = p.slice(5); }
  let file = path.join(root, path.normalize(p));
  if (!file.startsWith(root)) { res.writeHead(403).end(); return; }
  try { if (fs.statSync(file).isDirectory()) file = path.join(file, "index.html"); } catch {}
  let st;
  try { st = fs.statSync(file); } catch {
    if (root === APP) { file = path.join(APP, "index.html"); st = fs.statSync(file); } // SPA fallback
    else { res.writeHead(404).end("not found"); return; }
  }
  const h = { "Content-Type": MIME[path.extname(file)] ?? "application/octet-stream",
    "Accept-Ranges": "bytes", "Cache-Control": "no-cache",
    "Access-Control-Allow-Origin": "*", "Access-Control-Allow-Headers": "*",
    "Access-Control-Expose-Headers": "Content-Length, Content-Range, Accept-Ranges",
    "Cross-Origin-Opener-Policy": "same-origin", "Cross-Origin-Embedder-Policy": "credentialless",
    "Cross-Origin-Resource-Policy": "cross-origin" };
  if (req.method === "OPTIONS") { res.writeHead(204, h).end(); return; }
  const range = req.headers.range && /^bytes=(\d*)-(\d*)$/.exec(req.headers.range);
  if (range) {
    let start = range[1] === "" ? st.size - Number(range[2]) : Number(range[1]);
    let end = range[1] === "" || range[2] === "" ? st.size - 1 : Math.min(Number(range[2]), st.size - 1);
    if (start > end || start >= st.size) { res.writeHead(416, { ...h, "Content-Range": `bytes */${st.size}` }).end(); return; }
    res.writeHead(206, { ...h, "Content-Range": `bytes ${start}-${end}/${st.size}`, "Content-Length": end - start + 1 });
    if (req.method === "HEAD") { res.end(); return; }
    fs.createReadStream(file, { start, end }).pipe(res);
  } else {
    res.writeHead(200, { ...h, "Content-Length": st.size });
    if (req.method === "HEAD") { res.end(); return; }
    fs.createReadStream(file).pipe(res);
  }
}).listen(PORT, "127.0.0.1", () => console.log(`serving ${APP} and /data/ -> ${DATA} on http://127.0.0.1:${PORT}/`));
