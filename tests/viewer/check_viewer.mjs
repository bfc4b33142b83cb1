// Loads a recording in the viewer in headless Chromium and checks what it shows:
//   node check_viewer.mjs RECORDING_DIR VIEWER_DIR [OUTDIR]   (OUTDIR: screenshots kept there)
// Exit 0: pass; 1: fail; 77: skipped (Chromium or the viewer's node_modules missing).
import fs from 'node:fs';
import path from 'node:path';
import zlib from 'node:zlib';
import { pathToFileURL } from 'node:url';

const SKIP = 77;
const [recordingDir, viewerDir, saveDir] = process.argv.slice(2);
if (!recordingDir || !viewerDir) {
  console.error('usage: node check_viewer.mjs RECORDING_DIR VIEWER_DIR [OUTDIR]');
  process.exit(2);
}

const failures = [];
const check = (ok, message) => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${message}`);
  if (!ok) failures.push(message);
};

// Decodes an 8-bit, non-interlaced RGB or RGBA PNG (what Chromium's screenshots are).
function decodePng(buf) {
  if (buf.readUInt32BE(0) !== 0x89504e47) throw new Error('not a PNG');
  let off = 8, width = 0, height = 0, channels = 0;
  const idat = [];
  while (off < buf.length) {
    const len = buf.readUInt32BE(off);
    const type = buf.toString('ascii', off + 4, off + 8);
    const data = buf.subarray(off + 8, off + 8 + len);
    if (type === 'IHDR') {
      width = data.readUInt32BE(0);
      height = data.readUInt32BE(4);
      const depth = data[8], colourType = data[9], interlace = data[12];
      if (depth !== 8 || interlace !== 0 || (colourType !== 2 && colourType !== 6)) throw new Error('unsupported PNG');
      channels = colourType === 6 ? 4 : 3;
    } else if (type === 'IDAT') idat.push(data);
    off += 12 + len;
  }
  const raw = zlib.inflateSync(Buffer.concat(idat));
  const stride = width * channels;
  const px = Buffer.alloc(height * stride);
  for (let y = 0; y < height; ++y) {
    const filter = raw[y * (stride + 1)];
    const line = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    for (let x = 0; x < stride; ++x) {
      const a = x >= channels ? px[y * stride + x - channels] : 0;
      const b = y > 0 ? px[(y - 1) * stride + x] : 0;
      const c = x >= channels && y > 0 ? px[(y - 1) * stride + x - channels] : 0;
      let v = line[x];
      if (filter === 1) v += a;
      else if (filter === 2) v += b;
      else if (filter === 3) v += (a + b) >> 1;
      else if (filter === 4) {
        const p = a + b - c, pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
        v += pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      px[y * stride + x] = v & 0xff;
    }
  }
  return { width, height, channels, px };
}

// Hue [deg], saturation and value of an sRGB colour (channels in [0, 1]).
function hsv(r, g, b) {
  const max = Math.max(r, g, b), min = Math.min(r, g, b), d = max - min;
  let h = 0;
  if (d > 0) {
    if (max === r) h = 60 * (((g - b) / d) % 6);
    else if (max === g) h = 60 * ((b - r) / d + 2);
    else h = 60 * ((r - g) / d + 4);
  }
  return { h: (h + 360) % 360, s: max > 0 ? d / max : 0, v: max };
}

// Mask of pixels whose hue and saturation are those of `colour` (lighting changes brightness).
function colourMask(img, colour) {
  const want = hsv(...colour);
  const mask = new Uint8Array(img.width * img.height);
  for (let i = 0; i < mask.length; ++i) {
    const p = i * img.channels;
    const c = hsv(img.px[p] / 255, img.px[p + 1] / 255, img.px[p + 2] / 255);
    const dh = Math.min(Math.abs(c.h - want.h), 360 - Math.abs(c.h - want.h));
    mask[i] = dh < 20 && c.s > 0.5 * want.s && c.v > 0.12 ? 1 : 0;
  }
  return mask;
}

async function main() {
  const snapshot = await import(pathToFileURL(path.join(viewerDir, 'snapshot.mjs')).href);
  const { startServer } = await import(pathToFileURL(path.join(viewerDir, 'serve.mjs')).href);
  const { Recording } = await import(pathToFileURL(path.join(viewerDir, 'recording.js')).href);

  // Skip (not pass) when the browser or the npm dependencies are absent.
  const chromium = snapshot.findChromium();
  if (!chromium) {
    console.log(`SKIP: chromium not found ${process.env.DEXCLOTH_CHROMIUM ? `at DEXCLOTH_CHROMIUM=${process.env.DEXCLOTH_CHROMIUM}` : 'on PATH'}; run scripts/setup.sh to install it`);
    return SKIP;
  }
  for (const pkg of ['three', 'playwright-core']) {
    if (!fs.existsSync(path.join(viewerDir, 'node_modules', pkg, 'package.json'))) {
      console.log(`SKIP: ${path.join(viewerDir, 'node_modules', pkg)} missing; run scripts/setup.sh (npm ci in viewer/)`);
      return SKIP;
    }
  }

  // What the recording holds, read independently of the browser.
  const header = JSON.parse(fs.readFileSync(path.join(recordingDir, 'recording.json'), 'utf8'));
  const bin = fs.readFileSync(path.join(recordingDir, 'frames.bin'));
  const rec = new Recording(header, bin.buffer.slice(bin.byteOffset, bin.byteOffset + bin.byteLength));
  const last = header.frame_count - 1;
  check(header.frame_count > 1 && rec.frameCount === header.frame_count, `recording has ${header.frame_count} frames`);

  const server = await startServer({ recordingDir });
  const browser = await snapshot.launchBrowser(chromium);
  try {
    const width = 960, height = 600;
    const { page, errors } = await snapshot.openViewer(browser, server.url, { width, height });
    const frameCount = await page.evaluate(() => window.dexclothViewer.frameCount);
    check(frameCount === header.frame_count, `viewer frameCount ${frameCount} == ${header.frame_count}`);

    // First and last frames.
    const png0 = await snapshot.renderFrame(page, 0);
    const pngLast = await snapshot.renderFrame(page, last);
    const current = await page.evaluate(() => window.dexclothViewer.currentFrame);
    check(current === last, `currentFrame ${current} == ${last} after setFrame(${last})`);
    const hud = await page.evaluate(() => ({
      frame: document.getElementById('hud-frame').textContent,
      time: document.getElementById('hud-time').textContent,
      step: document.getElementById('hud-step').textContent,
    }));
    check(hud.frame === `${last} / ${last}`, `HUD frame "${hud.frame}" == "${last} / ${last}"`);
    const f = rec.frame(last);
    check(hud.time === `${f.t.toFixed(3)} s`, `HUD time "${hud.time}" == "${f.t.toFixed(3)} s"`);
    check(hud.step === `${f.stepMs.toFixed(2)} ms`, `HUD step "${hud.step}" == "${f.stepMs.toFixed(2)} ms"`);
    const clamped = await page.evaluate((k) => window.dexclothViewer.setFrame(k), header.frame_count + 5);
    check(clamped === last, `setFrame past the end clamps to ${last} (got ${clamped})`);
    const toggles = await page.evaluate(() => ({
      contacts: !document.getElementById('toggle-contacts').hidden,
      patches: !document.getElementById('toggle-patches').hidden,
    }));
    check(toggles.contacts && toggles.patches, 'contact and patch toggles shown for a recording that has them');

    // The cloth is drawn where it is: cloth-coloured pixels fill its projected rectangle and
    // (nearly) all cloth-coloured pixels lie inside it.
    const img = decodePng(pngLast);
    check(img.width === width && img.height === height, `screenshot is ${img.width}×${img.height}`);
    const box = await page.evaluate(() => window.dexclothViewer.clothScreenBox(0));
    const mask = colourMask(img, header.cloths[0].colour);
    let inside = 0, outside = 0;
    const x0 = Math.max(0, Math.floor(box.xmin) - 3), x1 = Math.min(width - 1, Math.ceil(box.xmax) + 3);
    const y0 = Math.max(0, Math.floor(box.ymin) - 3), y1 = Math.min(height - 1, Math.ceil(box.ymax) + 3);
    for (let y = 0; y < height; ++y) {
      for (let x = 0; x < width; ++x) {
        if (!mask[y * width + x]) continue;
        if (x >= x0 && x <= x1 && y >= y0 && y <= y1) ++inside; else ++outside;
      }
    }
    const boxArea = (x1 - x0 + 1) * (y1 - y0 + 1);
    console.log(`     cloth box [${x0}, ${x1}]×[${y0}, ${y1}], ${inside} cloth pixels inside, ${outside} outside`);
    check(boxArea > 0.02 * width * height, `cloth covers a fair part of the view (${(100 * boxArea / (width * height)).toFixed(1)} % of the image)`);
    check(inside > 0.3 * boxArea, `cloth colour fills its box (${(100 * inside / boxArea).toFixed(1)} % > 30 %)`);
    check(outside < 0.05 * (inside + outside), `cloth colour stays in its box (${outside} stray pixels)`);

    // The cloth moved between the first and last frames, and the picture shows it.
    const mask0 = colourMask(decodePng(png0), header.cloths[0].colour);
    let changed = 0;
    for (let i = 0; i < mask.length; ++i) changed += mask[i] !== mask0[i] ? 1 : 0;
    check(changed > 0.05 * inside, `frame 0 and frame ${last} differ (${changed} cloth pixels changed)`);

    check(errors.length === 0, `no console errors${errors.length ? `:\n  ${errors.join('\n  ')}` : ''}`);
    if (saveDir) {
      fs.mkdirSync(saveDir, { recursive: true });
      fs.writeFileSync(path.join(saveDir, 'first.png'), png0);
      fs.writeFileSync(path.join(saveDir, 'last.png'), pngLast);
    }
  } finally {
    await browser.close();
    await server.close();
  }
  console.log(failures.length ? `${failures.length} check(s) failed` : 'all checks passed');
  return failures.length ? 1 : 0;
}

main().then((code) => process.exit(code), (e) => {
  console.error(`check_viewer.mjs: ${e.stack ?? e.message}`);
  process.exit(1);
});
