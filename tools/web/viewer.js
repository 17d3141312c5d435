// The ESD-SLAM viewer page: a three.js scene (world = the first keyframe's camera, metres; camera
// frames x right, y down, z forward) and a panel with the current frame. Data arrive as
// server-sent events from esdslam (/events: "frame", "map", "status"); /snapshot gives the
// newest of each at load. ?once=1 loads the snapshot only (the headless browser test).
// `esdslam view` adds a "timeline" event (every frame's row of timing.csv, the poses with their
// times): a slider then steps through the run (stage times of that frame, trajectory up to it).
// When a frame has been drawn the title becomes "ESD-SLAM viewer: frame N" (tests read it).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const KEYPOINT_COLOURS = ['#3ddc5a', '#ff4040', '#ff40ff'];  // kept, semantic, geometry (KeypointKind)
const sceneBox = document.getElementById('scene');
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
renderer.setClearColor(0x15181d);
sceneBox.appendChild(renderer.domElement);
const scene = new THREE.Scene();
const camera = new THREE.PerspectiveCamera(60, 1, 0.01, 500);
camera.up.set(0, -1, 0);  // the world's y points down (camera convention)
camera.position.set(0, -2, -3);
const controls = new OrbitControls(camera, renderer.domElement);
let userMoved = false;
controls.addEventListener('start', () => { userMoved = true; });
scene.add(new THREE.AxesHelper(0.3));

const layers = {};  // name -> Object3D, replaced on every map event
function replaceLayer(name, object) {
  if (layers[name]) { scene.remove(layers[name]); layers[name].geometry?.dispose(); }
  layers[name] = object;
  if (object) scene.add(object);
}
function pointsObject(flat, colour, size, colours) {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.Float32BufferAttribute(flat, 3));
  const material = new THREE.PointsMaterial({ size, sizeAttenuation: false, color: colour });
  if (colours) {
    geometry.setAttribute('color', new THREE.Float32BufferAttribute(colours.map(c => c / 255), 3));
    material.vertexColors = true; material.color.set(0xffffff);
  }
  return new THREE.Points(geometry, material);
}
// Camera frustum lines (pose: tx ty tz qx qy qz qw, world_from_cam) of `size` metres.
function frustumSegments(poses, size) {
  const corners = [[-1, -0.75], [1, -0.75], [1, 0.75], [-1, 0.75]].map(([x, y]) => new THREE.Vector3(x * size, y * size, size * 1.2));
  const out = [];
  for (let i = 0; i + 6 < poses.length; i += 7) {
    const m = new THREE.Matrix4().compose(new THREE.Vector3(poses[i], poses[i + 1], poses[i + 2]),
      new THREE.Quaternion(poses[i + 3], poses[i + 4], poses[i + 5], poses[i + 6]), new THREE.Vector3(1, 1, 1));
    const c = corners.map(v => v.clone().applyMatrix4(m));
    const o = new THREE.Vector3(0, 0, 0).applyMatrix4(m);
    for (let k = 0; k < 4; ++k) out.push(o, c[k], c[k], c[(k + 1) % 4]);
  }
  return out.flatMap(v => [v.x, v.y, v.z]);
}
function segmentsObject(flat, colour) {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.Float32BufferAttribute(flat, 3));
  return new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color: colour }));
}
function lineObject(flat, colour) {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.Float32BufferAttribute(flat, 3));
  return new THREE.Line(geometry, new THREE.LineBasicMaterial({ color: colour }));
}
// Looks at everything from behind and above the first camera, until the user moves the view.
function fitView(flat) {
  if (userMoved || flat.length < 3) return;
  const box = new THREE.Box3().setFromArray(flat);
  const centre = box.getCenter(new THREE.Vector3());
  const radius = Math.max(0.5, box.getSize(new THREE.Vector3()).length() / 2);
  controls.target.copy(centre);
  camera.position.copy(centre).add(new THREE.Vector3(0, -0.8 * radius, -1.3 * radius));
  controls.update();
}

function onMap(map) {
  replaceLayer('dense', map.dense_points.length ? pointsObject(map.dense_points, 0xffffff, 2, map.dense_colors) : null);
  replaceLayer('static', pointsObject(map.static_points, 0xe6e6e6, 2));
  replaceLayer('dynamic', pointsObject(map.dynamic_points, 0xff4040, 3));
  replaceLayer('culled', pointsObject(map.culled_points || [], 0xff40ff, 5));
  replaceLayer('trajectory', lineObject(map.trajectory, 0x3ddc5a));
  replaceLayer('keyframes', segmentsObject(frustumSegments(map.keyframes, 0.05), 0x5a8cff));
  fitView(map.static_points.length ? map.static_points.concat(map.trajectory) : map.trajectory.concat(map.dense_points));
  setMetric('run', 'keyframes_in_map', map.keyframe_count);
  if (map.map_point_count >= 0) setMetric('run', 'map_points_in_map', map.map_point_count);
  setMetric('run', 'poses', map.trajectory_count);
}

function setMetric(table, name, value) {
  const body = document.querySelector('#' + table + ' tbody');
  let cell = body.querySelector('td[data-metric="' + name + '"]');
  if (!cell) {
    const row = body.insertRow();
    row.insertCell().textContent = name.replaceAll('_', ' ');
    cell = document.createElement('td');
    cell.setAttribute('data-metric', name);
    row.appendChild(cell);
  }
  cell.textContent = String(value);
}

function drawFrame(frame) {
  const canvas = document.getElementById('frame');
  const context = canvas.getContext('2d');
  const keypoints = frame.keypoints || [];
  const drawKeypoints = () => {
    for (let i = 0; i + 2 < keypoints.length; i += 3) {
      context.fillStyle = KEYPOINT_COLOURS[keypoints[i + 2]] || '#fff';
      context.fillRect(keypoints[i] - 1.5, keypoints[i + 1] - 1.5, 3, 3);
    }
    document.title = 'ESD-SLAM viewer: frame ' + frame.frames;
  };
  document.getElementById('frame-box').hidden = !frame.jpeg;  // a replay without debug pictures has none
  if (!frame.jpeg) { drawKeypoints(); return; }
  const image = new Image();
  image.onload = () => {
    canvas.width = frame.image_width; canvas.height = frame.image_height;
    context.drawImage(image, 0, 0);
    drawKeypoints();
  };
  image.src = 'data:image/jpeg;base64,' + frame.jpeg;
}

function onFrame(frame) {
  document.getElementById('mode').textContent = frame.replay ? 'replay' : 'live';
  for (const name of ['frames', 'keyframes', 'map_points', 'fps', 'state', 'dropped', 'viewer_dropped',
                      'keypoints_total', 'keypoints_dynamic', 'keypoints_geometry', 'timestamp']) {
    if (frame[name] !== undefined) setMetric('run', name, frame[name]);
  }
  for (const [name, ms] of Object.entries(frame.stages || {})) setMetric('stages', name, ms === null ? '-' : ms.toFixed(2));
  if (frame.has_pose && frame.pose) replaceLayer('camera', segmentsObject(frustumSegments(frame.pose, 0.12), 0xffd23d));
  drawFrame(frame);
}

function onStatus(status) {
  document.getElementById('connection').textContent = status.finished ? 'run finished' : 'running';
}

// Frame k of the timeline: its state and stage times, the trajectory up to its time (yellow).
function showTimelineFrame(timeline, k) {
  const t = timeline.timestamps ? timeline.timestamps[k] : Infinity;
  setMetric('replay', 'replay_frame', (timeline.rows[k] + 1) + ' / ' + (timeline.rows[timeline.rows.length - 1] + 1));
  if (timeline.timestamps) setMetric('replay', 'replay_time', t.toFixed(3));
  for (const [name, values] of Object.entries(timeline.text || {})) setMetric('replay', name, values[k]);
  for (const [name, values] of Object.entries(timeline.stages || {}))
    setMetric('stages', name, values[k] === null ? '-' : values[k].toFixed(2));
  let n = 0;
  while (n < timeline.pose_times.length && timeline.pose_times[n] <= t + 1e-6) ++n;
  const trail = timeline.positions.slice(0, 3 * n);
  replaceLayer('replay_trail', trail.length >= 6 ? lineObject(trail, 0xffd23d) : null);
  replaceLayer('replay_camera', trail.length >= 3 ? pointsObject(trail.slice(-3), 0xffd23d, 9) : null);
}

function onTimeline(timeline) {
  if (!timeline.rows.length) return;
  const box = document.getElementById('timeline');
  const scrub = document.getElementById('scrub');
  box.hidden = false;
  scrub.max = String(timeline.rows.length - 1);
  scrub.value = scrub.max;
  scrub.oninput = () => showTimelineFrame(timeline, Number(scrub.value));
  showTimelineFrame(timeline, timeline.rows.length - 1);
}

const handlers = { frame: onFrame, map: onMap, status: onStatus, timeline: onTimeline };
function apply(events) {
  for (const name of ['map', 'frame', 'status', 'timeline']) if (events[name]) handlers[name](events[name]);
}

function resize() {
  const w = sceneBox.clientWidth, h = sceneBox.clientHeight;
  renderer.setSize(w, h);
  camera.aspect = w / Math.max(1, h);
  camera.updateProjectionMatrix();
}
window.addEventListener('resize', resize);
resize();
renderer.setAnimationLoop(() => { controls.update(); renderer.render(scene, camera); });

const once = new URLSearchParams(location.search).has('once');
fetch('/snapshot').then(r => r.json()).then(events => {
  apply(events);
  if (once) { renderer.render(scene, camera); return; }
  const source = new EventSource('/events');
  for (const name of Object.keys(handlers)) source.addEventListener(name, e => handlers[name](JSON.parse(e.data)));
  source.onopen = () => { document.getElementById('connection').textContent = 'connected'; };
  source.onerror = () => { document.getElementById('connection').textContent = 'disconnected (the run ended?)'; };
});
