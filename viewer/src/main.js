// cmkit viewer: shows a glTF exported by `cmkit export` / `cmkit view` and
// the traces of a results file. URL parameters: model (default scene.glb),
// results (default results.txt; optional), audit (the findings of
// `cmkit audit --json`; optional).
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { describe, parseResults } from './results.js';

const params = new URLSearchParams(location.search);
const modelUrl = params.get('model') ?? 'scene.glb';
const resultsUrl = params.get('results') ?? 'results.txt';
const auditUrl = params.get('audit');

const canvas = document.getElementById('view');
const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x1c1e24);
scene.add(new THREE.HemisphereLight(0xffffff, 0x404050, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 1.4);
sun.position.set(0.35, 0.8, -0.5);
scene.add(sun);
const camera = new THREE.PerspectiveCamera(50, 1, 1, 100000);
const controls = new OrbitControls(camera, canvas);

// The map is z-up; the glTF root turns it y-up. Traces drawn from the
// results file get the same turn.
const zUp = new THREE.Group();
zUp.rotation.x = -Math.PI / 2;
scene.add(zUp);

const groups = { contents: new Map(), edges: [], internal: [], traces: new Map(), entities: new Map() };
let records = [];
let findings = [];
const findingGroup = new THREE.Group();
let selected = null;
// The highlighted entity: its name and its meshes' own materials, put back
// when another is picked.
let highlighted = null;

function resize() {
  const w = canvas.clientWidth;
  const h = canvas.clientHeight;
  renderer.setSize(w, h, false);
  camera.aspect = w / Math.max(h, 1);
  camera.updateProjectionMatrix();
}

// Cutting the scene above a height (map z, which is world y here) to look
// into rooms from above; the slider starts with the top fifth cut away.
const AUTO_CUT_FRACTION = 0.2;
const cutPlane = new THREE.Plane(new THREE.Vector3(0, -1, 0), 0);
renderer.clippingPlanes = [cutPlane];
function setupCut(object) {
  const box = new THREE.Box3().setFromObject(object);
  const slider = document.getElementById('cut');
  slider.min = String(Math.floor(box.min.y));
  slider.max = String(Math.ceil(box.max.y) + 1);
  slider.value = String(box.max.y - (box.max.y - box.min.y) * AUTO_CUT_FRACTION);
  const apply = () => {
    cutPlane.constant = Number(slider.value);
    document.getElementById('cut-value').textContent = slider.value;
  };
  slider.addEventListener('input', apply);
  apply();
}

function frame(object) {
  const box = new THREE.Box3().setFromObject(object);
  if (box.isEmpty()) return;
  const center = box.getCenter(new THREE.Vector3());
  const radius = box.getSize(new THREE.Vector3()).length() / 2 || 1;
  const dist = radius / Math.sin(THREE.MathUtils.degToRad(camera.fov / 2));
  camera.position.copy(center).add(new THREE.Vector3(-0.6, 0.7, 0.6).normalize().multiplyScalar(dist));
  camera.near = Math.max(dist / 1000, 0.1);
  camera.far = dist * 10;
  camera.updateProjectionMatrix();
  controls.target.copy(center);
  controls.update();
}

// Sorts the glTF's nodes into contents kinds, edges, internal edges, traces.
function classify(root) {
  root.traverse((obj) => {
    const x = obj.userData ?? {};
    if (obj.isMesh && obj.material) {
      // Faces sit a little behind their edges, so that edges do not flicker.
      obj.material.polygonOffset = true;
      obj.material.polygonOffsetFactor = 1;
      obj.material.polygonOffsetUnits = 1;
    }
    // Each model is an entity of the map (its name, class and origin when
    // the export had them): its polygons, edges and internal edges.
    if (x.model !== undefined && x.kind !== 'trace') {
      if (!groups.entities.has(x.model)) {
        groups.entities.set(x.model, { name: x.model, index: x.modelIndex ?? 0, classname: x.classname ?? '',
          origin: x.origin ?? null, objs: [] });
      }
      groups.entities.get(x.model).objs.push(obj);
    }
    if (x.kind === 'polygons') {
      const name = x.contentsNames || 'none';
      if (!groups.contents.has(name)) groups.contents.set(name, []);
      groups.contents.get(name).push(obj);
    } else if (x.kind === 'edges') {
      groups.edges.push(obj);
    } else if (x.kind === 'internal edges') {
      groups.internal.push(obj);
      obj.visible = false;
    } else if (x.kind === 'trace' && x.query !== undefined) {
      groups.traces.set(x.trace, obj);
    }
  });
}

// Lines for the traces of the results file that the glTF does not have.
function addTraceLines(recs) {
  const colors = { path: 0xffff00, rest: 0x808040, contact: 0xff0000, normal: 0xff8000 };
  for (const rec of recs) {
    if (groups.traces.has(rec.index) || rec.error || !rec.start) continue;
    const g = new THREE.Group();
    g.userData = { kind: 'trace', trace: rec.index };
    const seg = (a, b, color) => {
      const geo = new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(...a), new THREE.Vector3(...b)]);
      g.add(new THREE.LineSegments(geo, new THREE.LineBasicMaterial({ color })));
    };
    seg(rec.start, rec.endpos, colors.path);
    if (rec.end) seg(rec.endpos, rec.end, colors.rest);
    if (rec.point && rec.type !== 'none') {
      const s = 4;
      for (let k = 0; k < 3; ++k) {
        const a = [...rec.point];
        const b = [...rec.point];
        a[k] -= s;
        b[k] += s;
        seg(a, b, colors.contact);
      }
      if (rec.normal) seg(rec.point, rec.point.map((p, k) => p + rec.normal[k] * 16), colors.normal);
    }
    zUp.add(g);
    groups.traces.set(rec.index, g);
  }
}

function swatchColor(objs) {
  let color = '#888';
  objs[0]?.traverse((o) => {
    if (o.material?.color) color = '#' + o.material.color.getHexString(THREE.SRGBColorSpace);
  });
  return color;
}

function buildPanel() {
  const contentsDiv = document.getElementById('contents');
  for (const [name, objs] of [...groups.contents].sort()) {
    const label = document.createElement('label');
    label.innerHTML = `<input type="checkbox" checked data-contents="${name}" />` +
      `<span class="swatch" style="background:${swatchColor(objs)}"></span>${name}`;
    label.querySelector('input').addEventListener('change', (e) => {
      objs.forEach((o) => (o.visible = e.target.checked));
    });
    contentsDiv.appendChild(label);
  }
  const toggle = (id, objs) =>
    document.getElementById(id).addEventListener('change', (e) => objs().forEach((o) => (o.visible = e.target.checked)));
  toggle('show-edges', () => groups.edges);
  toggle('show-internal', () => groups.internal);
  toggle('show-traces', () => [...groups.traces.values()]);

  // Entity models: every model but the first (a map's world model).
  document.getElementById('show-entities').addEventListener('change', (e) => {
    for (const ent of groups.entities.values()) if (ent.index > 0) ent.objs.forEach((o) => (o.visible = e.target.checked));
  });
  const picker = document.getElementById('entities');
  for (const ent of [...groups.entities.values()].sort((a, b) => a.index - b.index)) {
    const option = document.createElement('option');
    option.value = ent.name;
    option.textContent = ent.classname ? `${ent.name} (${ent.classname})` : ent.name;
    picker.appendChild(option);
  }
  picker.addEventListener('change', () => {
    if (picker.value) selectEntity(picker.value, true);
  });

  const list = document.getElementById('traces');
  for (const rec of records) {
    const li = document.createElement('li');
    li.textContent = `${rec.op} ${rec.error ? 'error' : `fraction ${rec.fraction ?? '-'} ${rec.type}`}`;
    li.dataset.trace = rec.index;
    li.addEventListener('click', () => select(rec.index));
    list.appendChild(li);
  }
}

// Shows a trace's contact and highlights it.
function select(index) {
  selected = index;
  const rec = records[index];
  const obj = groups.traces.get(index);
  let text = rec ? describe(rec) : '';
  if (!rec && obj) {
    const x = obj.userData;
    text = [`#${index}`, x.query, `fraction: ${x.fraction}`, `contact: ${x.type}`, `point: ${x.point}`,
      `normal: ${x.normal}`, `contents: ${x.contents}`,
      `feature: model ${x.modelFeature}, trace model ${x.trmFeature}`].join('\n');
  }
  document.getElementById('info').textContent = text;
  document.querySelectorAll('#traces li').forEach((li) => li.classList.toggle('selected', +li.dataset.trace === index));
  document.body.dataset.selected = String(index);
}

// Shows an entity's name, class and origin and highlights its polygons;
// `frameIt` also turns the camera to it.
function selectEntity(name, frameIt = false) {
  const ent = groups.entities.get(name);
  if (!ent) return false;
  if (highlighted) highlighted.saved.forEach(([o, material]) => (o.material = material));
  highlighted = { name, saved: [] };
  for (const o of ent.objs) {
    if (!o.isMesh || !o.material?.emissive) continue;
    highlighted.saved.push([o, o.material]);
    o.material = o.material.clone();
    o.material.emissive = new THREE.Color(0x5a4a00);
  }
  const f = (v) => (v ? v.map((x) => +Number(x).toFixed(3)).join(', ') : '-');
  document.getElementById('info').textContent = [`entity ${ent.name}`, `class: ${ent.classname || '-'}`,
    `origin: ${f(ent.origin)}`, `model ${ent.index}`].join('\n');
  document.getElementById('entities').value = name;
  document.body.dataset.entity = name;
  if (frameIt) {
    const box = new THREE.Box3();
    ent.objs.forEach((o) => box.expandByObject(o));
    if (!box.isEmpty()) {
      const center = box.getCenter(new THREE.Vector3());
      const radius = Math.max(box.getSize(new THREE.Vector3()).length(), 64);
      camera.position.copy(center).add(camera.position.clone().sub(controls.target).normalize().multiplyScalar(radius * 2));
      controls.target.copy(center);
      controls.update();
    }
  }
  return true;
}

// The audit's findings: a marker per finding (a cross on the spot and a post
// above it, coloured by severity), numbered as in the JSON.
const SEVERITY_COLORS = { high: 0xff3030, medium: 0xff9000, low: 0xffe040 };
const FINDING_LISTS = ['fallouts', 'stuck', 'tunnels', 'embedded', 'open_shells'];
function addFindings(audit) {
  findings = FINDING_LISTS.flatMap((k) => audit[k] ?? []).filter((f) => Array.isArray(f.position));
  findings.sort((a, b) => (a.number ?? 0) - (b.number ?? 0));
  for (const f of findings) {
    const color = SEVERITY_COLORS[f.severity] ?? 0xffffff;
    const g = new THREE.Group();
    g.userData = { kind: 'finding', number: f.number };
    const [x, y, z] = f.position;
    const s = 12;
    const points = [[x - s, y, z], [x + s, y, z], [x, y - s, z], [x, y + s, z], [x, y, z - s], [x, y, z + 64]];
    const geo = new THREE.BufferGeometry().setFromPoints(points.map((p) => new THREE.Vector3(...p)));
    g.add(new THREE.LineSegments(geo, new THREE.LineBasicMaterial({ color, depthTest: false })));
    findingGroup.add(g);
  }
  zUp.add(findingGroup);
  const list = document.getElementById('findings');
  for (const f of findings) {
    const li = document.createElement('li');
    li.value = f.number;
    li.textContent = `${f.kind} (${f.severity})`;
    li.dataset.finding = f.number;
    li.addEventListener('click', () => selectFinding(f.number));
    list.appendChild(li);
  }
  document.getElementById('findings-section').hidden = false;
  document.getElementById('show-findings').addEventListener('change', (e) => (findingGroup.visible = e.target.checked));
}

// Shows a finding: what it is, where, and the way points that reached it (drawn).
let findingPath = null;
function selectFinding(number) {
  const f = findings.find((x) => x.number === number);
  if (!f) return false;
  const v = (p) => p.map((x) => +Number(x).toFixed(2)).join(', ');
  const lines = [`finding ${f.number}: ${f.kind}, ${f.severity}`, `at ${v(f.position)}`, f.what ?? ''];
  if (f.merged > 1) lines.push(`(${f.merged - 1} more of its kind nearby)`);
  if (Array.isArray(f.path) && f.path.length) lines.push('reached by:', ...f.path.map((p) => `  ${v(p)}`));
  document.getElementById('info').textContent = lines.join('\n');
  if (findingPath) findingGroup.remove(findingPath);
  findingPath = null;
  if (Array.isArray(f.path) && f.path.length > 1) {
    const geo = new THREE.BufferGeometry().setFromPoints(f.path.map((p) => new THREE.Vector3(...p)));
    findingPath = new THREE.Line(geo, new THREE.LineBasicMaterial({ color: 0x40e0ff, depthTest: false }));
    findingGroup.add(findingPath);
  }
  document.querySelectorAll('#findings li').forEach((li) => li.classList.toggle('selected', +li.dataset.finding === number));
  document.body.dataset.finding = String(number);
  return true;
}

const raycaster = new THREE.Raycaster();
function pick(event) {
  const rect = canvas.getBoundingClientRect();
  const ndc = new THREE.Vector2(((event.clientX - rect.left) / rect.width) * 2 - 1,
    -((event.clientY - rect.top) / rect.height) * 2 + 1);
  raycaster.setFromCamera(ndc, camera);
  // Lines are thin: accept hits within a few pixels' worth of world units.
  raycaster.params.Line.threshold = camera.position.distanceTo(controls.target) * 0.01;
  const targets = [...groups.traces.values()].filter((o) => o.visible);
  if (findingGroup.visible) targets.push(...findingGroup.children.filter((o) => o.userData?.kind === 'finding'));
  const hit = raycaster.intersectObjects(targets, true)[0];
  for (let o = hit?.object; o; o = o.parent) {
    if (o.userData?.kind === 'finding') {
      selectFinding(o.userData.number);
      return;
    }
  }
  if (!hit) {
    // No trace: the nearest visible polygon in front of the cut names its entity.
    const meshes = [...groups.entities.values()].flatMap((e) => e.objs).filter((o) => o.isMesh && o.visible);
    const face = raycaster.intersectObjects(meshes, false).find((h) => cutPlane.distanceToPoint(h.point) >= 0);
    if (face) selectEntity(face.object.userData.model);
    return;
  }
  for (let o = hit.object; o; o = o.parent) {
    if (o.userData?.kind === 'trace' && groups.traces.get(o.userData.trace) === o) {
      select(o.userData.trace);
      return;
    }
    if (o.userData?.kind === 'trace' && o.userData.trace !== undefined && !o.userData.query) {
      const owner = groups.traces.get(o.userData.trace);
      if (owner) {
        select(o.userData.trace);
        return;
      }
    }
  }
}
let downAt = null;
canvas.addEventListener('pointerdown', (e) => (downAt = [e.clientX, e.clientY]));
canvas.addEventListener('pointerup', (e) => {
  if (downAt && Math.hypot(e.clientX - downAt[0], e.clientY - downAt[1]) < 4) pick(e);
});

/** For tests: the screen position (CSS pixels) of a trace's path middle. */
function traceScreenPoint(index) {
  const rec = records[index];
  if (!rec?.start) return null;
  const mid = rec.start.map((s, k) => (s + rec.endpos[k]) / 2);
  const v = new THREE.Vector3(...mid).applyMatrix4(zUp.matrixWorld).project(camera);
  const rect = canvas.getBoundingClientRect();
  return { x: rect.left + ((v.x + 1) / 2) * rect.width, y: rect.top + ((1 - v.y) / 2) * rect.height };
}
/** For tests: the screen position (CSS pixels) of the centre of an entity's top (map z max). */
function entityScreenPoint(name) {
  const ent = groups.entities.get(name);
  if (!ent) return null;
  const box = new THREE.Box3();
  ent.objs.forEach((o) => box.expandByObject(o));
  const v = box.getCenter(new THREE.Vector3());
  v.y = box.max.y - 0.5;  // y is map z here: just under the top
  v.project(camera);
  const rect = canvas.getBoundingClientRect();
  return { x: rect.left + ((v.x + 1) / 2) * rect.width, y: rect.top + ((1 - v.y) / 2) * rect.height };
}
/** For tests: the screen position (CSS pixels) of a finding's spot. */
function findingScreenPoint(number) {
  const f = findings.find((x) => x.number === number);
  if (!f) return null;
  const v = new THREE.Vector3(...f.position).applyMatrix4(zUp.matrixWorld).project(camera);
  const rect = canvas.getBoundingClientRect();
  return { x: rect.left + ((v.x + 1) / 2) * rect.width, y: rect.top + ((1 - v.y) / 2) * rect.height };
}
window.cmkitViewer = { select, selectEntity, selectFinding, traceScreenPoint, entityScreenPoint, findingScreenPoint,
  get records() { return records; }, get findings() { return findings; } };

async function load() {
  const status = document.getElementById('status');
  try {
    const gltf = await new GLTFLoader().loadAsync(modelUrl);
    scene.add(gltf.scene);
    classify(gltf.scene);
    const res = await fetch(resultsUrl);
    if (res.ok) records = parseResults(await res.text());
    let auditNote = '';
    if (auditUrl) {
      try {
        const a = await fetch(auditUrl);
        if (!a.ok) throw new Error(`HTTP ${a.status}`);
        addFindings(await a.json());
        auditNote = `, ${findings.length} audit findings`;
      } catch (err) {
        auditNote = `, cannot read the audit ${auditUrl}: ${err.message ?? err}`;
      }
    }
    zUp.updateMatrixWorld(true);
    addTraceLines(records);
    buildPanel();
    resize();
    frame(gltf.scene);
    setupCut(gltf.scene);
    status.textContent = `${modelUrl}: ${groups.entities.size} models, ${groups.contents.size} contents kinds, ` +
      `${groups.traces.size} traces${auditNote}`;
    document.body.dataset.ready = '1';
  } catch (err) {
    status.textContent = `cannot load ${modelUrl}: ${err.message ?? err}`;
    document.body.dataset.ready = 'error';
  }
}

window.addEventListener('resize', resize);
renderer.setAnimationLoop(() => {
  controls.update();
  renderer.render(scene, camera);
});
resize();
load();
