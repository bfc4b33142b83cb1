#!/usr/bin/env node
// Renders a dexcloth recording in headless Chromium (Debian's, driven by playwright-core):
//   node snapshot.mjs DIR --frames 0,50,100 --png OUTDIR [--mp4 out.mp4] [--width 1280]
//                     [--height 720] [--fps N] [--chromium /usr/bin/chromium]
// PNGs are OUTDIR/frame_<k:06>.png; --mp4 encodes the chosen frames (all frames without
// --frames) with ffmpeg at the recording's frame rate (or --fps).
import { spawn, spawnSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import { startServer, checkDependencies, checkRecordingDir, viewerDir } from './serve.mjs';

const SETUP_HINT = 'run scripts/setup.sh (as root) to install it';

/** Chromium flags for software rendering in a headless, sandbox-less, offline container. */
export const chromiumArgs = [
  '--headless', '--no-sandbox', '--disable-gpu', '--no-first-run', '--disable-background-networking',
  '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-dev-shm-usage',
];

// First executable called `name` on PATH, or null.
function which(name) {
  if (name.includes('/')) return fs.existsSync(name) ? name : null;
  for (const dir of (process.env.PATH ?? '').split(path.delimiter)) {
    if (!dir) continue;
    const file = path.join(dir, name);
    try { fs.accessSync(file, fs.constants.X_OK); return file; } catch { /* keep looking */ }
  }
  return null;
}

/** The Chromium to use: `explicit`, $DEXCLOTH_CHROMIUM, or the first browser on PATH; or null. */
export function findChromium(explicit) {
  const wanted = explicit || process.env.DEXCLOTH_CHROMIUM;
  if (wanted) return which(wanted);
  for (const name of ['chromium', 'chromium-browser', 'google-chrome']) {
    const found = which(name);
    if (found) return found;
  }
  return null;
}

/** Launches headless Chromium through playwright-core (never downloads a browser). */
export async function launchBrowser(executablePath) {
  checkDependencies();
  const pw = path.join(viewerDir, 'node_modules', 'playwright-core', 'package.json');
  if (!fs.existsSync(pw)) throw new Error(`${path.dirname(pw)}: playwright-core is not installed; run scripts/setup.sh`);
  const { chromium } = await import('playwright-core');
  return chromium.launch({ executablePath, headless: true, args: chromiumArgs });
}

/**
 * Opens the viewer at `url` in a new page of `browser`, waits until the recording is shown, and
 * returns { page, errors } where errors collects console errors, page errors and failed requests.
 */
export async function openViewer(browser, url, { width = 1280, height = 720, snapshot = true } = {}) {
  const page = await browser.newPage({ viewport: { width, height }, deviceScaleFactor: 1 });
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(`console: ${m.text()}`); });
  page.on('pageerror', (e) => errors.push(`page error: ${e.message}`));
  page.on('requestfailed', (r) => errors.push(`request failed: ${r.url()} ${r.failure()?.errorText ?? ''}`));
  page.on('response', (r) => { if (r.status() >= 400) errors.push(`HTTP ${r.status()}: ${r.url()}`); });
  await page.goto(`${url}${snapshot ? '?snapshot' : ''}`, { waitUntil: 'load' });
  try {
    await page.evaluate(() => window.dexclothViewer.ready.then(() => true));
  } catch (e) {
    throw new Error(`viewer failed to load the recording: ${e.message}\n${errors.join('\n')}`);
  }
  return { page, errors };
}

/** Shows frame k and returns a PNG screenshot of the page (a Buffer). */
export async function renderFrame(page, k) {
  await page.evaluate((frame) => window.dexclothViewer.setFrame(frame), k);
  // Let the compositor present the frame before capturing it.
  await page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))));
  return page.screenshot({ type: 'png' });
}

function parseArgs(argv) {
  const args = { dir: null, frames: null, png: null, mp4: null, width: 1280, height: 720, fps: null, chromium: null };
  const value = (i, name) => {
    if (i >= argv.length) throw new Error(`${name}: missing value`);
    return argv[i];
  };
  for (let i = 0; i < argv.length; ++i) {
    const a = argv[i];
    if (a === '--frames') {
      const list = value(++i, a);
      args.frames = list.split(',').map((s) => s.trim());
      if (args.frames.some((s) => !/^\d+$/.test(s))) throw new Error(`--frames: expected a comma-separated list of frame numbers, got "${list}"`);
      args.frames = args.frames.map(Number);
    } else if (a === '--png') args.png = value(++i, a);
    else if (a === '--mp4') args.mp4 = value(++i, a);
    else if (a === '--width') args.width = Number(value(++i, a));
    else if (a === '--height') args.height = Number(value(++i, a));
    else if (a === '--fps') args.fps = Number(value(++i, a));
    else if (a === '--chromium') args.chromium = value(++i, a);
    else if (a === '-h' || a === '--help') args.help = true;
    else if (a.startsWith('--')) throw new Error(`unknown option ${a}`);
    else if (args.dir === null) args.dir = a;
    else throw new Error(`unexpected argument ${a}`);
  }
  if (args.help) return args;
  if (!args.dir) throw new Error('missing recording folder');
  if (!args.png && !args.mp4) throw new Error('nothing to do: give --png OUTDIR and/or --mp4 FILE');
  if (args.png && !args.frames) throw new Error('--png needs --frames, e.g. --frames 0,50,100');
  for (const k of ['width', 'height']) {
    if (!Number.isInteger(args[k]) || args[k] < 16 || args[k] > 8192) throw new Error(`--${k}: must be an integer in [16, 8192]`);
  }
  if (args.fps !== null && !(args.fps > 0)) throw new Error('--fps: must be > 0');
  return args;
}

// Encodes PNG buffers from `frames` (an async iterable) into an H.264 MP4 with ffmpeg.
async function encodeMp4(file, fps, frames) {
  const ffmpeg = spawn('ffmpeg', [
    '-hide_banner', '-loglevel', 'error', '-y',
    '-f', 'image2pipe', '-c:v', 'png', '-framerate', String(fps), '-i', '-',
    '-vf', 'scale=trunc(iw/2)*2:trunc(ih/2)*2',
    '-c:v', 'libx264', '-pix_fmt', 'yuv420p', '-crf', '18', '-preset', 'medium', '-movflags', '+faststart',
    file,
  ], { stdio: ['pipe', 'inherit', 'inherit'] });
  const done = new Promise((resolve, reject) => {
    ffmpeg.on('error', reject);
    ffmpeg.on('close', (code) => (code === 0 ? resolve() : reject(new Error(`ffmpeg exited with status ${code}`))));
  });
  for await (const png of frames) {
    if (!ffmpeg.stdin.write(png)) await new Promise((resolve) => ffmpeg.stdin.once('drain', resolve));
  }
  ffmpeg.stdin.end();
  await done;
}

async function main() {
  const usage = 'usage: node snapshot.mjs DIR --frames 0,50,100 --png OUTDIR [--mp4 out.mp4] [--width 1280] [--height 720] [--fps N] [--chromium PATH]';
  let args;
  try {
    args = parseArgs(process.argv.slice(2));
  } catch (e) {
    console.error(`snapshot.mjs: ${e.message}\n${usage}`);
    return 2;
  }
  if (args.help) { console.log(usage); return 0; }

  // Check every tool before starting anything.
  checkDependencies();
  checkRecordingDir(args.dir);
  const chromium = findChromium(args.chromium);
  if (!chromium) throw new Error(`chromium not found${args.chromium ? ` at ${args.chromium}` : ' on PATH'}; ${SETUP_HINT}`);
  if (args.mp4 && !which('ffmpeg')) throw new Error(`ffmpeg not found on PATH (needed for --mp4); ${SETUP_HINT}`);
  if (args.mp4 && spawnSync('ffmpeg', ['-hide_banner', '-encoders']).stdout?.toString().includes('libx264') === false) {
    throw new Error('ffmpeg has no libx264 encoder (needed for --mp4)');
  }

  const server = await startServer({ recordingDir: args.dir });
  let browser = null;
  try {
    browser = await launchBrowser(chromium);
    const { page, errors } = await openViewer(browser, server.url, { width: args.width, height: args.height });
    const { frameCount, header } = await page.evaluate(async () => {
      const v = await window.dexclothViewer.ready;
      const h = await (await fetch('recording/recording.json')).json();
      return { frameCount: v.frameCount, header: { scene: h.scene, frame_rate: h.frame_rate } };
    });
    const bad = (args.frames ?? []).filter((k) => k >= frameCount);
    if (bad.length) throw new Error(`--frames: ${bad.join(', ')} not in the recording (it has ${frameCount} frames)`);

    if (args.png) {
      fs.mkdirSync(args.png, { recursive: true });
      for (const k of args.frames) {
        const file = path.join(args.png, `frame_${String(k).padStart(6, '0')}.png`);
        fs.writeFileSync(file, await renderFrame(page, k));
        console.log(`wrote ${file}`);
      }
    }
    if (args.mp4) {
      const frames = args.frames ?? Array.from({ length: frameCount }, (_, k) => k);
      const fps = args.fps ?? header.frame_rate;
      fs.mkdirSync(path.dirname(path.resolve(args.mp4)), { recursive: true });
      async function* pngs() {
        for (let i = 0; i < frames.length; ++i) {
          yield await renderFrame(page, frames[i]);
          if (process.stdout.isTTY) process.stdout.write(`\rrendering frame ${i + 1}/${frames.length}`);
        }
        if (process.stdout.isTTY) process.stdout.write('\n');
      }
      await encodeMp4(args.mp4, fps, pngs());
      console.log(`wrote ${args.mp4} (${frames.length} frames at ${fps} fps)`);
    }
    if (errors.length) {
      console.error(`snapshot.mjs: the viewer reported errors:\n${errors.join('\n')}`);
      return 1;
    }
    return 0;
  } finally {
    if (browser) await browser.close();
    await server.close();
  }
}

if (process.argv[1] && import.meta.url === pathToFileURL(fs.realpathSync(process.argv[1])).href) {
  main().then((code) => process.exit(code), (e) => {
    console.error(`snapshot.mjs: ${e.message}`);
    process.exit(1);
  });
}
