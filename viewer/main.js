// dexcloth viewer: plays a recording (recording.json + frames.bin) with three.js.
// URL parameters: rec=<base url of the recording> (default "recording/"), frame=<k>,
// snapshot (hide the controls, pixel ratio 1: used by snapshot.mjs).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { loadRecording } from './recording.js';

const params = new URLSearchParams(window.location.search);
const snapshotMode = params.has('snapshot');
const recordingBase = params.get('rec') ?? 'recording/';

const $ = (id) => document.getElementById(id);
const ui = {
  scene: $('hud-scene'), time: $('hud-time'), frame: $('hud-frame'), step: $('hud-step'),
  message: $('message'), play: $('play'), scrubber: $('scrubber'), speed: $('speed'),
  contactsToggle: $('toggle-contacts'), patchesToggle: $('toggle-patches'),
  showContacts: $('show-contacts'), showPatches: $('show-patches'), fit: $('fit'),
};
if (snapshotMode) document.body.classList.add('snapshot');

// ---------------------------------------------------------------------------------------------
// Public handle for scripts and tests.

let resolveReady, rejectReady;
const ready = new Promise((resolve, reject) => { resolveReady = resolve; rejectReady = reject; });
const state = {
  recording: null,
  frame: 0,
  playing: false,
  speed: 1,
  playClock: 0,        // recorded seconds since play started, times speed
  playStartFrame: 0,
  lastTick: 0,
  dirty: true,
};
const view = {};       // three.js objects, filled by build()

window.dexclothViewer = {
  ready,
  get frameCount() { return state.recording ? state.recording.frameCount : 0; },
  get currentFrame() { return state.frame; },
  /** Shows frame k (clamped to the recording) and renders it now; returns the frame shown. */
  setFrame(k) { pause(); showFrame(k); return state.frame; },
  play() { play(); },
  pause() { pause(); },
  /** Screen rectangle (CSS pixels) covered by cloth i's vertices in the current frame. */
  clothScreenBox(i) { return clothScreenBox(i); },
};

// ---------------------------------------------------------------------------------------------
// Renderer, scene, camera.

const renderer = new THREE.WebGLRenderer({ antialias: true });
renderer.setPixelRatio(snapshotMode ? 1 : Math.min(window.devicePixelRatio, 2));
renderer.setSize(window.innerWidth, window.innerHeight);
renderer.outputColorSpace = THREE.SRGBColorSpace;
renderer.toneMapping = THREE.NeutralToneMapping;
renderer.toneMappingExposure = 1.0;
renderer.shadowMap.enabled = true;
renderer.shadowMap.type = THREE.PCFShadowMap;
$('viewport').appendChild(renderer.domElement);

const background = new THREE.Color(0xdde2e8);
const scene = new THREE.Scene();
scene.background = background;

const camera = new THREE.PerspectiveCamera(35, window.innerWidth / window.innerHeight, 0.01, 100);
const controls = new OrbitControls(camera, renderer.domElement);
controls.enableDamping = true;
controls.dampingFactor = 0.12;
controls.addEventListener('change', () => { state.dirty = true; });

// Recording content lives under `root`, rotated so the recording's up (-gravity) is +y.
const root = new THREE.Group();
scene.add(root);

function showError(message) {
  ui.message.hidden = false;
  ui.message.textContent = message;
  console.error(`dexcloth viewer: ${message}`);
}

// ---------------------------------------------------------------------------------------------
// Building the scene from the header.

const srgb = (c, fallback) => new THREE.Color().setRGB(...(c ?? fallback), THREE.SRGBColorSpace);

// A cloth as two one-sided meshes sharing positions: the front (faces as recorded) and the
// back (reversed winding, negated normals, a slightly darker shade). Each side then has its own
// outward normal, which shadow lookups offset along (one double-sided mesh would shadow the
// side facing the light).
function clothMesh(info) {
  const position = new THREE.BufferAttribute(new Float32Array(3 * info.vertex_count), 3);
  position.setUsage(THREE.DynamicDrawUsage);
  const faces = new Uint32Array(info.faces.flat());
  const reversed = faces.slice();
  for (let f = 0; f < reversed.length; f += 3) [reversed[f + 1], reversed[f + 2]] = [faces[f + 2], faces[f + 1]];
  const colour = srgb(info.colour, [0.8, 0.22, 0.18]);
  const side = (index, shade) => {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', position);
    geometry.setAttribute('normal', new THREE.BufferAttribute(new Float32Array(3 * info.vertex_count), 3).setUsage(THREE.DynamicDrawUsage));
    geometry.setIndex(new THREE.BufferAttribute(index, 1));
    const c = colour.clone().multiplyScalar(shade);
    const material = new THREE.MeshPhysicalMaterial({
      color: c,
      roughness: 0.82,
      metalness: 0.0,
      sheen: 1.0,
      sheenRoughness: 0.55,
      sheenColor: c.clone().lerp(new THREE.Color(1, 1, 1), 0.4),
      side: THREE.FrontSide,
      shadowSide: THREE.DoubleSide,
    });
    const mesh = new THREE.Mesh(geometry, material);
    mesh.receiveShadow = true;
    mesh.frustumCulled = false;  // vertices move every frame
    return mesh;
  };
  const front = side(faces, 1.0);
  const back = side(reversed, 0.82);
  front.castShadow = true;
  front.name = info.name;
  back.name = `${info.name} (back)`;
  const group = new THREE.Group();
  group.name = info.name;
  group.add(front, back);
  group.userData = { front, back };
  return group;
}

// Geometry of a rigid shape in its own frame (capsules along local z, planes in local x–y).
function shapeGeometry(s) {
  switch (s.type) {
    case 'box': return new THREE.BoxGeometry(s.size[0], s.size[1], s.size[2]);
    case 'sphere': return new THREE.SphereGeometry(s.radius, 40, 20);
    case 'capsule': return new THREE.CapsuleGeometry(s.radius, s.length, 10, 28).rotateX(Math.PI / 2);
    case 'plane': return new THREE.PlaneGeometry(s.size[0], s.size[1]);
    case 'mesh': {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(s.vertices.flat()), 3));
      g.setIndex(s.faces.flat());
      return g.toNonIndexed();
    }
    default: throw new Error(`rigid shape ${s.name}: unknown type ${s.type}`);
  }
}

// Points in the shape frame whose hull holds the shape (planes: none, they do not frame).
function shapeHullPoints(s) {
  const pts = [];
  const corners = (hx, hy, hz) => {
    for (let i = 0; i < 8; ++i) pts.push(new THREE.Vector3(i & 1 ? hx : -hx, i & 2 ? hy : -hy, i & 4 ? hz : -hz));
  };
  switch (s.type) {
    case 'box': corners(s.size[0] / 2, s.size[1] / 2, s.size[2] / 2); break;
    case 'sphere': corners(s.radius, s.radius, s.radius); break;
    case 'capsule': corners(s.radius, s.radius, s.radius + s.length / 2); break;
    case 'mesh': for (const v of s.vertices) pts.push(new THREE.Vector3(...v)); break;
    default: break;
  }
  return pts;
}

function shapeMesh(s) {
  const material = new THREE.MeshStandardMaterial({
    color: srgb(s.colour, [0.62, 0.66, 0.72]),
    roughness: s.type === 'plane' ? 0.95 : 0.5,
    metalness: 0.05,
    flatShading: s.type === 'mesh' || s.type === 'box',
    side: s.type === 'plane' ? THREE.DoubleSide : THREE.FrontSide,
  });
  const mesh = new THREE.Mesh(shapeGeometry(s), material);
  mesh.name = s.name;
  mesh.castShadow = s.type !== 'plane';
  mesh.receiveShadow = true;
  return mesh;
}

// Points of the recording's content in three.js world space, over a sample of frames (at most
// ~20k points): cloth vertices and the hull points of the rigid shapes.
function contentPoints(rec) {
  const points = [];
  const n = rec.frameCount;
  const frames = [];
  const step = Math.max(1, Math.floor(n / 40));
  for (let k = 0; k < n; k += step) frames.push(k);
  if (n > 0 && frames[frames.length - 1] !== n - 1) frames.push(n - 1);
  const vertices = rec.header.cloths.reduce((sum, c) => sum + c.vertex_count, 0);
  const stride = 3 * Math.max(1, Math.ceil(vertices * frames.length / 20000));
  const hulls = rec.header.rigid_shapes.map(shapeHullPoints);
  const q = new THREE.Quaternion();
  for (const k of frames) {
    const f = rec.frame(k);
    for (const x of f.cloths) {
      for (let i = 0; i < x.length; i += stride) points.push(new THREE.Vector3(x[i], x[i + 1], x[i + 2]));
    }
    hulls.forEach((hull, j) => {
      q.fromArray(f.poses, 7 * j + 3);
      const p = new THREE.Vector3().fromArray(f.poses, 7 * j);
      for (const h of hull) points.push(h.clone().applyQuaternion(q).add(p));
    });
  }
  for (const p of points) p.applyQuaternion(root.quaternion);
  if (points.length === 0) points.push(new THREE.Vector3(-0.5, 0, -0.5), new THREE.Vector3(0.5, 1, 0.5));
  return points;
}

// Grid on the ground, 2n cells of size `cell` each way, every fifth line stronger. Lines are
// cut into cell-long segments: software rasterisers (SwiftShader, used for headless snapshots)
// drop whole lines that cross the camera's near plane.
function groundGrid(cell, n) {
  const minor = [], major = [];
  const half = n * cell;
  for (let i = -n; i <= n; ++i) {
    const target = i % 5 === 0 ? major : minor;
    const c = i * cell;
    for (let j = -n; j < n; ++j) {
      const a = j * cell, b = (j + 1) * cell;
      target.push(a, 0, c, b, 0, c, c, 0, a, c, 0, b);
    }
  }
  const group = new THREE.Group();
  for (const [points, colour, opacity] of [[minor, 0xaab3bf, 0.45], [major, 0x8e99a8, 0.7]]) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.Float32BufferAttribute(points, 3));
    const lines = new THREE.LineSegments(geometry,
      new THREE.LineBasicMaterial({ color: colour, transparent: true, opacity, depthWrite: false }));
    lines.frustumCulled = false;
    group.add(lines);
  }
  group.userData.halfSize = half;
  return group;
}

// A round number near x (1, 2 or 5 times a power of ten).
function niceStep(x) {
  const e = Math.pow(10, Math.floor(Math.log10(x)));
  const m = x / e;
  return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * e;
}

function build(rec) {
  const h = rec.header;
  // Up = -gravity.
  const g = new THREE.Vector3(...(h.gravity ?? [0, 0, -9.81]));
  const up = g.lengthSq() > 0 ? g.clone().negate().normalize() : new THREE.Vector3(0, 0, 1);
  root.quaternion.setFromUnitVectors(up, new THREE.Vector3(0, 1, 0));
  root.updateMatrixWorld(true);

  view.cloths = h.cloths.map((c) => { const m = clothMesh(c); root.add(m); return m; });
  view.shapes = h.rigid_shapes.map((s) => { const m = shapeMesh(s); root.add(m); return m; });

  // Frame the content: bounds, ground height, grid, lights, camera.
  view.points = contentPoints(rec);
  const bounds = new THREE.Box3().setFromPoints(view.points);
  view.bounds = bounds;
  const sphere = bounds.getBoundingSphere(new THREE.Sphere());
  const R = Math.max(sphere.radius, 0.05);
  view.radius = R;
  // The ground: a horizontal plane shape if there is one, else y = 0 when the content sits
  // just above it, else the lowest point of the content.
  let groundY = bounds.min.y >= -1e-3 * R && bounds.min.y < 1.5 * R ? Math.min(0, bounds.min.y) : bounds.min.y;
  const f0 = rec.frameCount > 0 ? rec.frame(0) : null;
  let planeIsGround = false;
  h.rigid_shapes.forEach((s, j) => {
    if (s.type !== 'plane' || !f0) return;
    const q = new THREE.Quaternion().fromArray(f0.poses, 7 * j + 3);
    const n = new THREE.Vector3(0, 0, 1).applyQuaternion(q).applyQuaternion(root.quaternion);
    if (n.y > 0.999) {
      groundY = new THREE.Vector3().fromArray(f0.poses, 7 * j).applyQuaternion(root.quaternion).y;
      planeIsGround = true;
    }
  });
  view.groundY = groundY;

  const extent = 2 * Math.max(R * 10, 1);
  const ground = new THREE.Mesh(
    new THREE.PlaneGeometry(extent * 4, extent * 4).rotateX(-Math.PI / 2),
    new THREE.MeshStandardMaterial({ color: 0xe4e7eb, roughness: 1, metalness: 0 }));
  ground.position.y = groundY - 1e-4 * R;
  ground.receiveShadow = true;
  ground.visible = !planeIsGround;
  scene.add(ground);

  const cell = niceStep(R / 4);
  const grid = groundGrid(cell, Math.min(200, Math.round(extent / cell / 2)));
  grid.position.set(Math.round(sphere.center.x / cell) * cell, groundY + 2e-4 * R, Math.round(sphere.center.z / cell) * cell);
  scene.add(grid);
  scene.fog = new THREE.Fog(background, 7 * R, 16 * R);  // range set by fitCamera()

  // Lights: soft sky/ground fill, a shadow-casting key light from the upper front left, a rim.
  // (No image-based environment: prefiltering it takes seconds in software renderers.)
  scene.add(new THREE.HemisphereLight(0xf4f7ff, 0x8f877d, 1.7));
  const key = new THREE.DirectionalLight(0xfff4e6, 2.8);
  key.position.copy(sphere.center).add(new THREE.Vector3(-0.55, 1.0, 0.75).normalize().multiplyScalar(4 * R));
  key.target.position.copy(sphere.center);
  key.castShadow = true;
  key.shadow.mapSize.set(2048, 2048);
  const sc = key.shadow.camera;
  sc.left = -2 * R; sc.right = 2 * R; sc.top = 2 * R; sc.bottom = -2 * R;
  sc.near = 0.5 * R; sc.far = 8 * R;
  key.shadow.bias = -0.0008;
  key.shadow.normalBias = 0.01 * R;
  key.shadow.radius = 3;
  scene.add(key, key.target);
  const rim = new THREE.DirectionalLight(0xdfe8ff, 0.8);
  rim.position.copy(sphere.center).add(new THREE.Vector3(0.8, 0.5, -0.9).multiplyScalar(4 * R));
  scene.add(rim);
  // A soft fill from the camera side, so faces turned from the key light keep their shape.
  view.fill = new THREE.DirectionalLight(0xffffff, 0.7);
  scene.add(view.fill, view.fill.target);

  buildOverlays(rec, R);
  fitCamera();
}

// Contact points with force lines, and rigid cloth patches, sized for the busiest frame.
function buildOverlays(rec, R) {
  const maxContacts = Math.max(0, ...rec.index.contacts);
  const maxPatches = Math.max(0, ...rec.index.patches);
  view.contacts = null;
  view.patches = null;
  if (maxContacts > 0) {
    let maxForce = 0;
    for (let k = 0; k < rec.frameCount; ++k) {
      const c = rec.frame(k).contacts;
      for (let i = 0; i < c.length; i += 9) maxForce = Math.max(maxForce, Math.hypot(c[i + 6], c[i + 7], c[i + 8]));
    }
    const dots = new THREE.InstancedMesh(new THREE.SphereGeometry(1, 12, 8),
      new THREE.MeshBasicMaterial({ color: 0xffc21a, depthTest: false, transparent: true }), maxContacts);
    dots.renderOrder = 10;
    dots.frustumCulled = false;
    const lines = new THREE.LineSegments(new THREE.BufferGeometry(),
      new THREE.LineBasicMaterial({ color: 0xd9480f, depthTest: false, transparent: true }));
    lines.geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(6 * maxContacts), 3).setUsage(THREE.DynamicDrawUsage));
    lines.renderOrder = 11;
    lines.frustumCulled = false;
    const group = new THREE.Group();
    group.add(dots, lines);
    root.add(group);
    view.contacts = { group, dots, lines, dotRadius: 0.01 * R, forceScale: maxForce > 0 ? 0.25 * R / maxForce : 0 };
    ui.contactsToggle.hidden = false;
    group.visible = ui.showContacts.checked;
  }
  if (maxPatches > 0) {
    const boxes = new THREE.InstancedMesh(new THREE.BoxGeometry(1, 1, 1),
      new THREE.MeshStandardMaterial({ color: 0x1c7ed6, transparent: true, opacity: 0.55, depthWrite: false }), maxPatches);
    boxes.frustumCulled = false;
    boxes.renderOrder = 5;
    root.add(boxes);
    view.patches = { boxes, minThickness: 0.004 * R };
    ui.patchesToggle.hidden = false;
    boxes.visible = ui.showPatches.checked;
  }
}

// Looks at the content from a three-quarter view (the recording's -y side for z-up, from
// above) at the distance where every content point is in view.
function fitCamera() {
  const box = view.bounds;
  const centre = box.getCenter(new THREE.Vector3());
  const back = new THREE.Vector3(0.38, 0.5, 1).normalize();  // from the target to the camera
  const right = new THREE.Vector3(0, 1, 0).cross(back).normalize();
  const up = back.clone().cross(right);
  const tanV = Math.tan(THREE.MathUtils.degToRad(camera.fov) / 2) * 0.86;  // margin
  const tanH = tanV * camera.aspect;
  let distance = 0;
  const o = new THREE.Vector3();
  for (const p of view.points) {
    o.subVectors(p, centre);
    const a = o.dot(back);
    distance = Math.max(distance, a + Math.abs(o.dot(right)) / tanH, a + Math.abs(o.dot(up)) / tanV);
  }
  distance = Math.max(distance, 0.2);
  camera.position.copy(centre).addScaledVector(back, distance);
  camera.near = distance / 100;
  camera.far = distance * 50;
  camera.updateProjectionMatrix();
  controls.target.copy(centre);
  controls.update();
  view.fill.position.copy(camera.position).add(new THREE.Vector3(0, distance, 0));
  view.fill.target.position.copy(centre);
  // The ground fades into the background beyond the content.
  scene.fog.near = 1.4 * distance;
  scene.fog.far = 4 * distance;
  state.dirty = true;
}

// ---------------------------------------------------------------------------------------------
// Frames.

const tmpMatrix = new THREE.Matrix4();
const tmpPos = new THREE.Vector3();
const tmpQuat = new THREE.Quaternion();
const tmpScale = new THREE.Vector3();

function applyFrame(k) {
  const rec = state.recording;
  const f = rec.frame(k);
  view.cloths.forEach((group, c) => {
    const { front, back } = group.userData;
    const position = front.geometry.getAttribute('position');
    position.array.set(f.cloths[c]);
    position.needsUpdate = true;
    front.geometry.computeVertexNormals();  // area-weighted smooth normals
    const n = front.geometry.getAttribute('normal').array;
    const nb = back.geometry.getAttribute('normal');
    for (let i = 0; i < n.length; ++i) nb.array[i] = -n[i];
    nb.needsUpdate = true;
  });
  view.shapes.forEach((mesh, j) => {
    mesh.position.fromArray(f.poses, 7 * j);
    mesh.quaternion.fromArray(f.poses, 7 * j + 3);
  });
  if (view.contacts) {
    const { dots, lines, dotRadius, forceScale } = view.contacts;
    const n = f.contacts.length / 9;
    const line = lines.geometry.getAttribute('position');
    for (let i = 0; i < n; ++i) {
      const c = f.contacts.subarray(9 * i, 9 * i + 9);
      tmpMatrix.compose(tmpPos.set(c[0], c[1], c[2]), tmpQuat.identity(), tmpScale.setScalar(dotRadius));
      dots.setMatrixAt(i, tmpMatrix);
      line.setXYZ(2 * i, c[0], c[1], c[2]);
      line.setXYZ(2 * i + 1, c[0] + forceScale * c[6], c[1] + forceScale * c[7], c[2] + forceScale * c[8]);
    }
    dots.count = n;
    dots.instanceMatrix.needsUpdate = true;
    line.needsUpdate = true;
    lines.geometry.setDrawRange(0, 2 * n);
  }
  if (view.patches) {
    const { boxes, minThickness } = view.patches;
    const n = f.patches.length / 10;
    for (let i = 0; i < n; ++i) {
      const p = f.patches.subarray(10 * i, 10 * i + 10);
      tmpScale.set(Math.max(p[7], minThickness), Math.max(p[8], minThickness), Math.max(p[9], minThickness));
      tmpMatrix.compose(tmpPos.set(p[0], p[1], p[2]), tmpQuat.set(p[3], p[4], p[5], p[6]), tmpScale);
      boxes.setMatrixAt(i, tmpMatrix);
    }
    boxes.count = n;
    boxes.instanceMatrix.needsUpdate = true;
  }
  updateHud(k, f);
}

function updateHud(k, f) {
  const h = state.recording.header;
  ui.time.textContent = `${f.t.toFixed(3)} s`;
  ui.frame.textContent = `${k} / ${state.recording.frameCount - 1}`;
  ui.step.textContent = f.stepMs > 0 ? `${f.stepMs.toFixed(2)} ms` : '–';
  ui.scene.textContent = h.complete ? h.scene : `${h.scene} (unfinished)`;
  ui.scrubber.value = String(k);
}

function showFrame(k) {
  const rec = state.recording;
  if (!rec || rec.frameCount === 0) return;
  state.frame = Math.min(Math.max(0, Math.round(Number(k) || 0)), rec.frameCount - 1);
  applyFrame(state.frame);
  render();
}

function render() {
  renderer.render(scene, camera);
  state.dirty = false;
}

function clothScreenBox(i) {
  const mesh = view.cloths?.[i]?.userData.front;
  if (!mesh) throw new Error(`no cloth ${i}`);
  const x = mesh.geometry.getAttribute('position');
  const width = renderer.domElement.clientWidth, height = renderer.domElement.clientHeight;
  const box = { xmin: Infinity, ymin: Infinity, xmax: -Infinity, ymax: -Infinity };
  const p = new THREE.Vector3();
  for (let v = 0; v < x.count; ++v) {
    p.fromBufferAttribute(x, v).applyMatrix4(mesh.matrixWorld).project(camera);
    const sx = (p.x + 1) / 2 * width, sy = (1 - p.y) / 2 * height;
    box.xmin = Math.min(box.xmin, sx); box.xmax = Math.max(box.xmax, sx);
    box.ymin = Math.min(box.ymin, sy); box.ymax = Math.max(box.ymax, sy);
  }
  return box;
}

// ---------------------------------------------------------------------------------------------
// Playback and controls.

function play() {
  const rec = state.recording;
  if (!rec || rec.frameCount < 2) return;
  if (state.frame >= rec.frameCount - 1) state.frame = 0;
  state.playing = true;
  state.playStartFrame = state.frame;
  state.playClock = 0;
  state.lastTick = performance.now();
  ui.play.textContent = '❚❚';
}

function pause() {
  state.playing = false;
  ui.play.textContent = '▶';
}

function tick(now) {
  requestAnimationFrame(tick);
  const rec = state.recording;
  if (!rec) return;
  if (state.playing) {
    state.playClock += (now - state.lastTick) / 1000 * state.speed;
    state.lastTick = now;
    const k = state.playStartFrame + Math.floor(state.playClock * rec.header.frame_rate);
    if (k >= rec.frameCount - 1) { showFrame(rec.frameCount - 1); pause(); }
    else if (k !== state.frame) showFrame(k);
  }
  if (controls.update() || state.dirty) render();
}

function wireControls() {
  ui.play.addEventListener('click', () => (state.playing ? pause() : play()));
  ui.scrubber.addEventListener('input', () => { pause(); showFrame(ui.scrubber.value); });
  ui.speed.addEventListener('change', () => {
    const k = state.frame;
    state.speed = Number(ui.speed.value);
    if (state.playing) { state.playStartFrame = k; state.playClock = 0; }
  });
  ui.showContacts.addEventListener('change', () => {
    if (view.contacts) view.contacts.group.visible = ui.showContacts.checked;
    state.dirty = true;
  });
  ui.showPatches.addEventListener('change', () => {
    if (view.patches) view.patches.boxes.visible = ui.showPatches.checked;
    state.dirty = true;
  });
  ui.fit.addEventListener('click', fitCamera);
  window.addEventListener('keydown', (e) => {
    if (e.target instanceof HTMLInputElement && e.target.type !== 'range' && e.target.type !== 'checkbox') return;
    const n = state.recording?.frameCount ?? 0;
    if (e.key === ' ') { e.preventDefault(); state.playing ? pause() : play(); }
    else if (e.key === 'ArrowRight') { pause(); showFrame(state.frame + 1); }
    else if (e.key === 'ArrowLeft') { pause(); showFrame(state.frame - 1); }
    else if (e.key === 'Home') { pause(); showFrame(0); }
    else if (e.key === 'End') { pause(); showFrame(n - 1); }
    else if (e.key === 'f') fitCamera();
  });
  window.addEventListener('resize', () => {
    camera.aspect = window.innerWidth / window.innerHeight;
    camera.updateProjectionMatrix();
    renderer.setSize(window.innerWidth, window.innerHeight);
    state.dirty = true;
  });
}

// ---------------------------------------------------------------------------------------------
// Start.

async function start() {
  const rec = await loadRecording(recordingBase);
  state.recording = rec;
  if (rec.frameCount === 0) throw new Error(`${recordingBase}: the recording has no frames yet`);
  build(rec);
  ui.scrubber.max = String(rec.frameCount - 1);
  ui.speed.value = '1';
  wireControls();
  showFrame(params.get('frame') ?? 0);
  requestAnimationFrame(tick);
}

ready.catch(() => {});  // reported by showError; callers see the rejection
start().then(
  () => resolveReady(window.dexclothViewer),
  (error) => { showError(error.message ?? String(error)); rejectReady(error); });
