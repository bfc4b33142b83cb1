#!/usr/bin/env node
// Serves the dexcloth viewer for one recording folder:
//   node serve.mjs DIR [--port P] [--host 127.0.0.1]
// /                 viewer files (index.html, main.js, recording.js, style.css)
// /vendor/three/    three.js from node_modules (build/ and examples/jsm/ only)
// /recording/       DIR's recording.json and frames.bin
// Nothing is fetched from the network: the viewer works offline.
import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

export const viewerDir = path.dirname(fileURLToPath(import.meta.url));
const threeDir = path.join(viewerDir, 'node_modules', 'three');
const viewerFiles = new Set(['index.html', 'main.js', 'recording.js', 'style.css']);
const recordingFiles = new Set(['recording.json', 'frames.bin']);
const types = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8',
  '.css': 'text/css; charset=utf-8',
  '.json': 'application/json; charset=utf-8',
  '.bin': 'application/octet-stream',
};

/** Throws an Error with a setup hint if the viewer's npm dependencies are missing. */
export function checkDependencies() {
  if (!fs.existsSync(path.join(threeDir, 'package.json'))) {
    throw new Error(`${threeDir}: three.js is not installed; run scripts/setup.sh (it runs \`npm ci\` in viewer/)`);
  }
}

/** Throws an Error naming the file if `dir` is not a recording folder. */
export function checkRecordingDir(dir) {
  for (const name of recordingFiles) {
    const file = path.join(dir, name);
    if (!fs.existsSync(file)) throw new Error(`${file}: not found (is ${dir} a dexcloth recording folder?)`);
  }
}

// The file a URL path maps to, or null. Only whitelisted files; no path escapes its root.
function resolveFile(urlPath, recordingDir) {
  let p;
  try { p = decodeURIComponent(urlPath); } catch { return null; }
  if (p.includes('\0')) return null;
  if (p === '/') return path.join(viewerDir, 'index.html');
  if (p.startsWith('/recording/')) {
    const name = p.slice('/recording/'.length);
    return recordingFiles.has(name) ? path.join(recordingDir, name) : null;
  }
  if (p.startsWith('/vendor/three/')) {
    const rel = path.posix.normalize(p.slice('/vendor/three/'.length));
    if (!(rel.startsWith('build/') || rel.startsWith('examples/jsm/'))) return null;
    const file = path.join(threeDir, rel);
    return file.startsWith(threeDir + path.sep) ? file : null;
  }
  const name = p.slice(1);
  return viewerFiles.has(name) ? path.join(viewerDir, name) : null;
}

/**
 * Starts the server. `port` 0 picks a free port. Resolves to { url, server, close() }.
 */
export async function startServer({ recordingDir, port = 0, host = '127.0.0.1', log = false }) {
  checkDependencies();
  checkRecordingDir(recordingDir);
  const dir = path.resolve(recordingDir);
  const server = http.createServer((req, res) => {
    const url = new URL(req.url, 'http://localhost');
    if (req.method !== 'GET' && req.method !== 'HEAD') {
      res.writeHead(405, { Allow: 'GET, HEAD' }).end();
      return;
    }
    const file = resolveFile(url.pathname, dir);
    const fail = (code) => {
      if (log) console.error(`${code} ${url.pathname}`);
      res.writeHead(code, { 'Content-Type': 'text/plain; charset=utf-8' }).end(`${code}\n`);
    };
    if (!file) return fail(404);
    fs.stat(file, (err, st) => {
      if (err || !st.isFile()) return fail(404);
      res.writeHead(200, {
        'Content-Type': types[path.extname(file)] ?? 'application/octet-stream',
        'Content-Length': st.size,
        'Cache-Control': 'no-store',  // recordings may be rewritten while served
      });
      if (req.method === 'HEAD') return res.end();
      fs.createReadStream(file).on('error', () => res.destroy()).pipe(res);
    });
  });
  await new Promise((resolve, reject) => {
    server.once('error', reject);
    server.listen(port, host, resolve);
  });
  const address = server.address();
  const shownHost = address.family === 'IPv6' ? `[${address.address}]` : address.address;
  return {
    server,
    url: `http://${shownHost}:${address.port}/`,
    close: () => new Promise((resolve) => { server.closeAllConnections?.(); server.close(resolve); }),
  };
}

function parseArgs(argv) {
  const args = { dir: null, port: 8080, host: '127.0.0.1' };
  for (let i = 0; i < argv.length; ++i) {
    const a = argv[i];
    if (a === '--port') args.port = Number(argv[++i]);
    else if (a === '--host') args.host = argv[++i];
    else if (a === '-h' || a === '--help') args.help = true;
    else if (a.startsWith('--')) throw new Error(`unknown option ${a}`);
    else if (args.dir === null) args.dir = a;
    else throw new Error(`unexpected argument ${a}`);
  }
  if (args.help) return args;
  if (!args.dir) throw new Error('missing recording folder');
  if (!Number.isInteger(args.port) || args.port < 0 || args.port > 65535) throw new Error('--port: must be an integer in [0, 65535]');
  if (!args.host) throw new Error('--host: missing value');
  return args;
}

async function main() {
  const usage = 'usage: node serve.mjs DIR [--port 8080] [--host 127.0.0.1]';
  let args;
  try {
    args = parseArgs(process.argv.slice(2));
  } catch (e) {
    console.error(`serve.mjs: ${e.message}\n${usage}`);
    process.exit(2);
  }
  if (args.help) { console.log(usage); return; }
  try {
    const { url } = await startServer({ recordingDir: args.dir, port: args.port, host: args.host, log: true });
    console.log(`dexcloth viewer: ${url}  (serving ${path.resolve(args.dir)}; Ctrl-C to stop)`);
  } catch (e) {
    console.error(`serve.mjs: ${e.code === 'EADDRINUSE' ? `port ${args.port} is in use; pick another with --port` : e.message}`);
    process.exit(1);
  }
  process.on('SIGINT', () => process.exit(0));
  process.on('SIGTERM', () => process.exit(0));
}

if (process.argv[1] && import.meta.url === pathToFileURL(fs.realpathSync(process.argv[1])).href) main();
