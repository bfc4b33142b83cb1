#!/usr/bin/env node
// Robustness sweep of a hand's pinch: runs a pinch scene from N perturbed starts (every cloth
// shifted by a seeded random 0–0.5 mm in x, y, z and turned by up to ±0.1° about the vertical;
// every wrist-driven hand's whole path shifted by up to ±0.5 mm and turned by up to ±0.2° about
// the vertical) and reports, per run and in all, whether the cloth was carried. A run holds when every probe
// named "pinched*" stays within 30 mm of both pad probes (thumb_tip, index_pad) from the last
// handle's release on (or from --from seconds) and rises more than 12 cm (or --rise metres)
// with the hand, with no intersection and no NaN.
//
//   node scripts/hold_sweep.mjs scenes/pinch_move.json [--runs 20] [--jobs 2] [--threads 1]
//                [--seed 1] [--exe build/dexcloth] [--out out/sweep] [--set /ptr=value ...]
//   node scripts/hold_sweep.mjs scenes/curtain_hand.json --from 0.8 --rise -1   (a sideways pull)
//   node scripts/hold_sweep.mjs scenes/pinch_move.json --only 10,13   (those starts of the
//                same seeded sweep, alone: to look again at a run that dropped; --runs is then
//                ignored)
// (--threads: each run's; the runs' results do not depend on it.)
import { spawn } from "node:child_process";
import { mkdirSync, readFileSync } from "node:fs";
import { basename, dirname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";

const here = dirname(fileURLToPath(import.meta.url));
const args = process.argv.slice(2);
const option = (name, fallback) => {
  const k = args.indexOf(name);
  return k >= 0 ? args[k + 1] : fallback;
};
const scenePath = args.find((a, k) => !a.startsWith("--") && (k === 0 || !args[k - 1].startsWith("--")));
if (!scenePath) {
  console.error("usage: node scripts/hold_sweep.mjs <scene.json> [--runs N] [--only K,...] [--jobs J] [--threads T] [--seed S] [--exe PATH] [--out DIR] [--from S] [--rise M] [--set /ptr=value ...]");
  process.exit(2);
}
const onlyText = option("--only", "");
const only = onlyText === "" ? null : onlyText.split(",").map(Number);
if (only && only.some((k) => !Number.isInteger(k) || k < 0)) {
  console.error(`--only: expected start numbers such as 3,10, got '${onlyText}'`);
  process.exit(2);
}
// Starts are drawn in order from the seeded generator, so start k is the same whatever the count.
const runs = only ? Math.max(...only) + 1 : Number(option("--runs", "20"));
const chosen = only ?? Array.from({ length: runs }, (_, k) => k);
const jobs = Number(option("--jobs", "2"));
const threads = option("--threads", "1");
const seed = Number(option("--seed", "1"));
const exe = resolve(option("--exe", join(here, "..", "build", "dexcloth")));
const name = basename(scenePath, ".json");
const outRoot = resolve(option("--out", join(here, "..", "out", "sweep", name)));
const extraSets = args.flatMap((a, k) => (a === "--set" ? ["--set", args[k + 1]] : []));

const scene = JSON.parse(readFileSync(scenePath, "utf8"));
const release = Number(option("--from",
  String(Math.max(...scene.cloths.flatMap((c) => (c.handles ?? []).map((h) => h.release ?? 0))))));
const minimumRise = Number(option("--rise", "0.12"));
const pinchedProbes = (scene.probes ?? []).map((p) => p.name).filter((n) => n.startsWith("pinched"));
if (pinchedProbes.length === 0) {
  console.error(`${scenePath}: no probe named pinched*`);
  process.exit(2);
}

// Seeded generator (mulberry32), so a sweep is repeatable.
function generator(s) {
  return () => {
    s |= 0;
    s = (s + 0x6d2b79f5) | 0;
    let t = Math.imul(s ^ (s >>> 15), 1 | s);
    t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t;
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}
const random = generator(seed);

// The perturbed starts: run 0 is the scene as it is.
const starts = [];
for (let r = 0; r < runs; ++r) {
  const sets = [];
  scene.cloths.forEach((c, k) => {
    const t = c.transform?.translation ?? [0, 0, 0];
    const rot = c.transform?.rotation_deg ?? [0, 0, 0];
    const d = r === 0 ? [0, 0, 0] : [0, 1, 2].map(() => 0.0005 * random());
    const turn = r === 0 ? 0 : 0.2 * (random() - 0.5);
    sets.push(`/cloths/${k}/transform/translation=[${t.map((v, i) => v + d[i]).join(",")}]`);
    sets.push(`/cloths/${k}/transform/rotation_deg=[${rot[0]},${rot[1]},${rot[2] + turn}]`);
  });
  (scene.bodies ?? []).forEach((b, k) => {
    const keys = b.controller?.wrist?.keyframes;
    if (!keys || r === 0) return;
    const d = [0, 1, 2].map(() => 0.001 * (random() - 0.5));
    const turn = 0.4 * (random() - 0.5);
    const moved = (pose) => [
      `translation=[${pose.translation.map((v, i) => v + d[i]).join(",")}]`,
      `rotation_deg=[${(pose.rotation_deg ?? [0, 0, 0]).map((v, i) => (i === 2 ? v + turn : v)).join(",")}]`,
    ];
    if (b.root?.translation) moved(b.root).forEach((m) => sets.push(`/bodies/${k}/root/${m}`));
    keys.forEach((key, q) => {
      if (key.translation) moved(key).forEach((m) => sets.push(`/bodies/${k}/controller/wrist/keyframes/${q}/${m}`));
    });
  });
  starts.push(sets);
}

function distance(a, b) {
  return Math.hypot(a[1] - b[1], a[2] - b[2], a[3] - b[3]);
}

// One run's outcome from its summary.json.
function outcome(summary) {
  const probes = summary.probes;
  let farthest = 0;
  let rise = Infinity;
  for (const p of pinchedProbes) {
    const s = probes[p];
    let zRelease = s[0][3];
    for (let k = 0; k < s.length; ++k) {
      if (s[k][0] <= release + 1e-9) zRelease = s[k][3];
      if (s[k][0] >= release - 1e-9)
        farthest = Math.max(farthest, distance(s[k], probes.thumb_tip[k]), distance(s[k], probes.index_pad[k]));
    }
    rise = Math.min(rise, s[s.length - 1][3] - zRelease);
  }
  const intact = summary.intersections_max === 0 && !summary.nan;
  return { held: farthest < 0.03 && rise > minimumRise && intact, farthest, rise, intact,
           warnings: summary.warnings_total, stepMs: summary.step_ms.median };
}

function runOne(r) {
  const out = join(outRoot, `run_${String(r).padStart(2, "0")}`);
  mkdirSync(dirname(out), { recursive: true });
  const argv = ["run", resolve(scenePath), "--quiet", "--threads", threads, "--out", out,
                ...starts[r].flatMap((s) => ["--set", s]), ...extraSets];
  return new Promise((done) => {
    const child = spawn(exe, argv, { stdio: ["ignore", "ignore", "pipe"] });
    let err = "";
    child.stderr.on("data", (d) => (err += d));
    child.on("close", (code) => {
      if (code !== 0) return done({ r, failed: `exit ${code}: ${err.trim()}` });
      done({ r, ...outcome(JSON.parse(readFileSync(join(out, "summary.json"), "utf8"))) });
    });
  });
}

const results = [];
let next = 0;
async function worker() {
  while (next < chosen.length) {
    const r = chosen[next++];
    const res = await runOne(r);
    results.push(res);
    const line = res.failed
      ? `run ${r}: FAILED ${res.failed}`
      : `run ${r}: ${res.held ? "held" : "DROPPED"}  farthest ${(1e3 * res.farthest).toFixed(1)} mm  rise ${(1e2 * res.rise).toFixed(1)} cm  ` +
        `intact ${res.intact}  warnings ${res.warnings}  median ${res.stepMs.toFixed(1)} ms/step`;
    console.log(`${line}   [${starts[r].join(" ")}]`);
  }
}
await Promise.all(Array.from({ length: jobs }, worker));

const done = results.filter((x) => !x.failed);
const held = done.filter((x) => x.held).length;
const worst = Math.max(...done.map((x) => x.farthest));
const minRise = Math.min(...done.map((x) => x.rise));
console.log(`${name}: ${held}/${chosen.length} held, ${done.length - held} dropped, ${chosen.length - done.length} failed; ` +
            `worst pinched-point distance ${(1e3 * worst).toFixed(1)} mm, least rise ${(1e2 * minRise).toFixed(1)} cm`);
process.exit(held === chosen.length ? 0 : 1);
