// Plays one rollout (docs/design.md §11): the cloth as a shaded two-sided mesh coloured by a
// per-vertex value, the handle targets as spheres, the scene's obstacles translucent, an orbit
// camera, play/pause, a time slider, the speed, a colour bar and the per-step plots. All frames are
// fetched once as Float32Arrays; a frame change only copies one frame's positions and colours into
// the mesh (and an animated mesh obstacle's vertices into its own).
import * as THREE from "/three/build/three.module.js";
import { OrbitControls } from "/three/examples/jsm/controls/OrbitControls.js";
import { NO_VALUE, drawColourRamp, viridis } from "/colour_map.js";
import { createSeriesPlots } from "/series_plots.js";

async function fetchChecked(url) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: ${(await response.text()).trim() || response.status}`);
  return response;
}

const binary = (url, Type) => fetchChecked(url).then((r) => r.arrayBuffer()).then((b) => new Type(b));

// A mesh obstacle's triangles and vertices (its vertex_frames frames of vertex_count each), from
// the endpoints under `url`.
async function fetchObstacleMesh(url) {
  const [triangles, vertices] = await Promise.all([
    binary(`${url}/triangles`, Int32Array),
    binary(`${url}/vertices`, Float32Array),
  ]);
  return { triangles, vertices };
}

// The largest frame index whose time is at most `time`.
function frameAt(times, time) {
  let low = 0, high = times.length - 1;
  while (low < high) {
    const middle = (low + high + 1) >> 1;
    if (times[middle] <= time) low = middle;
    else high = middle - 1;
  }
  return low;
}

function boundsOf(positions) {
  const box = new THREE.Box3();
  const point = new THREE.Vector3();
  for (let k = 0; k < positions.length; k += 3) box.expandByPoint(point.fromArray(positions, k));
  return box;
}

// A mesh obstacle's geometry at its first vertex frame, in the scene's coordinates.
function meshObstacleGeometry(o, arrays) {
  const geometry = new THREE.BufferGeometry();
  const usage = o.vertex_frames > 1 ? THREE.DynamicDrawUsage : THREE.StaticDrawUsage;
  const first = arrays.vertices.slice(0, 3 * o.vertex_count);
  geometry.setAttribute("position", new THREE.BufferAttribute(first, 3).setUsage(usage));
  geometry.setIndex(new THREE.BufferAttribute(new Uint32Array(arrays.triangles.buffer), 1));
  geometry.computeVertexNormals();
  return geometry;
}

// Frame f of an animated mesh obstacle's vertices into its geometry, with the normals and the
// bounding sphere (for culling) that follow them.
function showMeshObstacleFrame(geometry, o, vertices, f) {
  const position = geometry.getAttribute("position");
  position.array.set(vertices.subarray(3 * o.vertex_count * f, 3 * o.vertex_count * (f + 1)));
  position.needsUpdate = true;
  geometry.computeVertexNormals();
  geometry.computeBoundingSphere();
}

// An obstacle's mesh (docs/design.md §14), placed at its t = 0 pose; a plane as a square twice the
// scene's size. Rounded boxes are drawn with sharp edges. A mesh obstacle's `arrays` (from
// fetchObstacleMesh) are in the scene's coordinates, so only the offsets move its group.
function obstacleMesh(o, size, arrays) {
  const material = new THREE.MeshPhongMaterial({ color: 0x8899aa, transparent: true, opacity: 0.55, side: THREE.DoubleSide });
  const point = new THREE.Vector3().fromArray(o.point), axis = new THREE.Vector3().fromArray(o.axis);
  const group = new THREE.Group();
  if (o.shape === "sphere") {
    group.add(new THREE.Mesh(new THREE.SphereBufferGeometry(o.radius, 32, 16), material));
  } else if (o.shape === "box") {
    group.add(new THREE.Mesh(new THREE.BoxBufferGeometry(axis.x, axis.y, axis.z), material));
  } else if (o.shape === "plane") {
    const plane = new THREE.Mesh(new THREE.PlaneBufferGeometry(2 * size, 2 * size), material);
    plane.quaternion.setFromUnitVectors(new THREE.Vector3(0, 0, 1), axis);
    group.add(plane);
  } else if (o.shape === "capsule") {
    const along = axis.clone().sub(point), length = along.length();
    // Open-ended: the end discs would show through the translucent caps.
    const side = new THREE.CylinderBufferGeometry(o.radius, o.radius, length, 32, 1, true);
    const cylinder = new THREE.Mesh(side, material);
    cylinder.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), along.clone().normalize());
    cylinder.position.copy(along).multiplyScalar(0.5);
    group.add(cylinder);
    for (const end of [new THREE.Vector3(), along]) {
      const cap = new THREE.Mesh(new THREE.SphereBufferGeometry(o.radius, 24, 12), material);
      cap.position.copy(end);
      group.add(cap);
    }
  } else if (o.shape === "mesh") {
    group.userData.geometry = meshObstacleGeometry(o, arrays);
    group.add(new THREE.Mesh(group.userData.geometry, material));
  }
  const base = o.shape === "mesh" ? new THREE.Vector3() : point;
  group.position.copy(base);
  group.userData.base = base;
  return group;
}

function createScene(stage, meta, positions, faces, obstacleArrays) {
  const N = meta.rows * meta.cols;
  const renderer = new THREE.WebGLRenderer({ antialias: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setClearColor(0xffffff);
  stage.replaceChildren(renderer.domElement);
  const scene = new THREE.Scene();
  scene.add(new THREE.HemisphereLight(0xffffff, 0x555555, 0.7));
  const sun = new THREE.DirectionalLight(0xffffff, 0.6);
  sun.position.set(1, -2, 3);
  scene.add(sun);

  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute("position", new THREE.BufferAttribute(positions.slice(0, 3 * N), 3).setUsage(THREE.DynamicDrawUsage));
  geometry.setAttribute("color", new THREE.BufferAttribute(new Float32Array(3 * N), 3).setUsage(THREE.DynamicDrawUsage));
  geometry.setIndex(new THREE.BufferAttribute(new Uint32Array(faces.buffer), 1));
  const material = new THREE.MeshPhongMaterial({ vertexColors: THREE.VertexColors, side: THREE.DoubleSide, shininess: 8 });
  scene.add(new THREE.Mesh(geometry, material));

  // Frame everything the cloth ever covers: the camera looks at the motion's centre, z up.
  const box = boundsOf(positions);
  const centre = box.getCenter(new THREE.Vector3());
  const size = Math.max(box.getSize(new THREE.Vector3()).length(), 1e-3);
  const handles = [];
  const sphere = new THREE.SphereBufferGeometry(0.012 * size, 16, 12);
  const handleMaterial = new THREE.MeshPhongMaterial({ color: 0xd62728 });
  for (let h = 0; h < meta.handle_count; ++h) {
    handles.push(new THREE.Mesh(sphere, handleMaterial));
    scene.add(handles[h]);
  }
  const obstacles = meta.obstacles.map((o, k) => obstacleMesh(o, size, obstacleArrays[k]));
  for (const mesh of obstacles) scene.add(mesh);
  const grid = new THREE.GridHelper(size * 1.5, 10, 0xcccccc, 0xe4e4e4);
  grid.rotation.x = Math.PI / 2;
  grid.position.set(centre.x, centre.y, box.min.z);
  scene.add(grid);

  const camera = new THREE.PerspectiveCamera(40, 1, size * 0.01, size * 20);
  camera.up.set(0, 0, 1);
  camera.position.copy(centre).add(new THREE.Vector3(0.35, -1.0, 0.35).multiplyScalar(size));
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.target.copy(centre);
  controls.update();

  const resize = () => {
    const width = stage.clientWidth, height = stage.clientHeight;
    renderer.setSize(width, height);
    camera.aspect = width / Math.max(height, 1);
    camera.updateProjectionMatrix();
  };
  resize();
  new ResizeObserver(resize).observe(stage);
  return { renderer, scene, camera, geometry, handles, obstacles };
}

export async function showRollout(id) {
  const base = `/api/rollouts/${id}`;
  const meta = await (await fetchChecked(`${base}/meta`)).json();
  const [positions, faces, strain, distance, obstacleArrays] = await Promise.all([
    binary(`${base}/positions`, Float32Array),
    binary(`${base}/faces`, Int32Array),
    binary(`${base}/strain`, Float32Array),
    meta.reference ? binary(`${base}/distance`, Float32Array) : null,
    Promise.all(meta.obstacles.map((o, k) => (o.shape === "mesh" ? fetchObstacleMesh(`${base}/obstacles/${k}`) : null))),
  ]);
  const N = meta.rows * meta.cols, T = meta.frames, H = meta.handle_count;
  document.getElementById("rollout").hidden = false;
  document.getElementById("title").textContent = meta.name;
  const subtitle = document.getElementById("subtitle");
  subtitle.title = meta.optimizer;
  subtitle.textContent =
    `${meta.kind}, ${meta.rows}\u00d7${meta.cols}, ${T} frames` +
    (meta.optimizer ? `, ${meta.optimizer.split(":")[0]}` : "") +
    (meta.reference ? `, against ${meta.reference}` : "") +
    (meta.divergence ? `; diverged: ${meta.divergence}` : "");

  const view = createScene(document.getElementById("stage"), meta, positions, faces, obstacleArrays);
  const plots = createSeriesPlots(document.getElementById("plots"), meta);
  const slider = document.getElementById("time");
  const timeLabel = document.getElementById("time-label");
  const playButton = document.getElementById("play");
  const speedSelect = document.getElementById("speed");
  const colourSelect = document.getElementById("colour-by");
  slider.max = T - 1;
  colourSelect.querySelector("option[value=distance]").disabled = !distance;
  colourSelect.value = distance ? "distance" : "strain";
  drawColourRamp(document.getElementById("colour-ramp"));

  // The colour range is fixed over the rollout, so that colours compare across frames.
  const colouring = () =>
    colourSelect.value === "distance"
      ? { values: distance, high: meta.max_distance, scale: 1000, unit: "mm", label: `distance to ${meta.reference}` }
      : { values: strain, high: meta.max_strain, scale: 100, unit: "%", label: "edge strain (largest of the vertex's edges)" };
  const showColourBar = () => {
    const c = colouring();
    document.getElementById("colour-min").textContent = `0 ${c.unit}`;
    document.getElementById("colour-max").textContent = `${(c.high * c.scale).toPrecision(3)} ${c.unit}`;
    document.getElementById("colour-label").textContent = c.label;
  };

  let frame = -1, time = meta.times[0], playing = true, last = null;
  const showFrame = (f) => {
    frame = f;
    const position = view.geometry.getAttribute("position");
    position.array.set(positions.subarray(3 * N * f, 3 * N * (f + 1)));
    position.needsUpdate = true;
    view.geometry.computeVertexNormals();
    const { values, high } = colouring();
    const range = high > 0 ? high : 1;  // all zero (a rollout against itself): all at the low end
    const colour = view.geometry.getAttribute("color");
    for (let k = 0; k < N; ++k) {
      const v = values[N * f + k];
      colour.array.set(Number.isFinite(v) ? viridis(v / range) : NO_VALUE, 3 * k);
    }
    colour.needsUpdate = true;
    for (let h = 0; h < H; ++h) view.handles[h].position.fromArray(meta.handle_positions, 3 * (H * f + h));
    view.obstacles.forEach((group, k) => {
      const o = meta.obstacles[k];
      group.position.fromArray(o.offsets, 3 * f).add(group.userData.base);
      if (o.vertex_frames > 1) showMeshObstacleFrame(group.userData.geometry, o, obstacleArrays[k].vertices, f);
    });
    slider.value = f;
    timeLabel.textContent = `t = ${meta.times[f].toFixed(3)} s (frame ${f}/${T - 1})`;
    plots.setTime(meta.times[f]);
  };

  playButton.onclick = () => {
    playing = !playing;
    playButton.textContent = playing ? "Pause" : "Play";
  };
  slider.oninput = () => {
    time = meta.times[Number(slider.value)];
    showFrame(Number(slider.value));
  };
  colourSelect.onchange = () => {
    showColourBar();
    showFrame(frame);
  };
  showColourBar();

  const tick = (now) => {
    if (playing && last !== null) {
      time += ((now - last) / 1000) * Number(speedSelect.value);
      if (time > meta.times[T - 1]) time = meta.times[0];
    }
    last = now;
    const f = frameAt(meta.times, time);
    if (f !== frame) showFrame(f);
    view.renderer.render(view.scene, view.camera);
    requestAnimationFrame(tick);
  };
  showFrame(0);
  view.renderer.render(view.scene, view.camera);
  document.getElementById("status").textContent = "";
  requestAnimationFrame(tick);
}
