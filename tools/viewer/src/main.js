// The page `strata view` writes: the level, each agent profile's navmesh (by island or by tile; one profile
// shown at a time), tile borders coloured by that profile's tile states, bodies (sensors see-through), agents
// walking to their targets along the timeline with their paths, and characters walking their routes, over
// the frames of a recorded demo or simulate run. The address may choose what shows first: ?profile=N&frame=N.
// data.js sets window.STRATA_VIEW (the recording, prepared by ViewerFolder) and window.STRATA_GLB (scene.glb
// as base64), so the page also works opened straight from disk, where a browser refuses to fetch files.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { LineMaterial } from 'three/addons/lines/LineMaterial.js';
import { LineSegments2 } from 'three/addons/lines/LineSegments2.js';
import { LineSegmentsGeometry } from 'three/addons/lines/LineSegmentsGeometry.js';

// Colours are shown exactly as the file stores them (no sRGB conversion), so a navmesh island's colour on
// screen is the one the recording names: the browser test looks for it in a screenshot.
THREE.ColorManagement.enabled = false;

const TILE_STATE_COLOURS = {
  missing: 0x707070,
  queued: 0xc8a0ff,
  building: 0x3070ff,
  ready: 0x30c050,
  stale: 0xffa020,
};
const TILE_STATES = ['missing', 'queued', 'building', 'ready', 'stale'];
// One colour a profile for its agents (the first profile's green as before).
const PROFILE_COLOURS = [0x30d060, 0xe07030, 0x40a0f0, 0xd0d040, 0xc050c0];

// The profile a glTF layer belongs to: "navmesh" and "paths" are the first's, "navmesh_2" the third's.
function layerProfile(name) {
  const match = /_(\d+)$/.exec(name);
  return match ? Number(match[1]) : 0;
}

function decodeBase64(text) {
  const binary = atob(text);
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; ++i) bytes[i] = binary.charCodeAt(i);
  return bytes.buffer;
}

function tileColour(x, z) {
  // Neighbouring tiles in different colours: a hash of the coordinates onto a hue.
  const hue = (((x * 73856093) ^ (z * 19349663)) >>> 0) % 360;
  return new THREE.Color().setHSL(hue / 360, 0.65, 0.55);
}

function shapeGeometry(shape) {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.Float32BufferAttribute(shape.positions, 3));
  geometry.setIndex(shape.indices);
  geometry.computeVertexNormals();
  return geometry;
}

class Viewer {
  constructor(view, glb) {
    this.view = view;
    // Positions in data.js and scene.glb are relative to this point of the world (ViewerFolder).
    this.origin = view.origin || [0, 0, 0];
    this.frame = 0;
    this.playing = false;
    this.profiles = view.profiles && view.profiles.length > 0 ? view.profiles : [{ name: 'navmesh' }];
    this.profile = 0;
    this.layers = {};
    this.renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
    this.renderer.outputColorSpace = THREE.LinearSRGBColorSpace;
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.renderer.setSize(window.innerWidth, window.innerHeight);
    document.getElementById('canvas-host').appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0x1d2128);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x404040, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.2);
    sun.position.set(0.4, 1.0, 0.3);
    this.scene.add(sun);
    this.camera = new THREE.PerspectiveCamera(50, window.innerWidth / window.innerHeight, 0.1, 1e6);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.addEventListener('change', () => this.render());
    window.addEventListener('resize', () => this.resize());
    this.glb = glb;
  }

  async load() {
    if (this.glb) {
      const gltf = await new GLTFLoader().parseAsync(this.glb, '');
      const objects = [];
      gltf.scene.traverse((object) => objects.push(object));
      for (const object of objects) this.adoptGltfObject(object);
      this.scene.add(gltf.scene);
    }
    this.addTileBorders();
    this.addBodies();
    this.addAgents();
    this.addCharacters();
    this.frameCamera();
    this.setupControls();
    const asked = new URLSearchParams(window.location.search);
    const lastFrame = Math.max(this.view.frames.length - 1, 0);
    const frame = asked.has('frame') ? Math.min(Math.max(Number(asked.get('frame')) || 0, 0), lastFrame) : lastFrame;
    const profile = Math.min(Math.max(Number(asked.get('profile')) || 0, 0), this.profiles.length - 1);
    this.showProfile(profile);
    this.showFrame(frame);
    this.render();
    this.publishStats();
  }

  // The file's layers by name: the level shaded, the navmesh and paths in their own colours, unlit.
  adoptGltfObject(object) {
    if (!object.isMesh && !object.isLine && !object.isLineSegments) return;
    const name = object.name || (object.parent && object.parent.name) || '';
    const layer = ['level', 'navmesh', 'paths'].find((known) => name.startsWith(known));
    if (!layer) return;
    object.userData.profile = layerProfile(name);
    if (layer === 'level') {
      object.material = new THREE.MeshLambertMaterial({ vertexColors: true, side: THREE.DoubleSide });
      object.geometry.computeVertexNormals();
    } else if (layer === 'navmesh') {
      object.material = new THREE.MeshBasicMaterial({
        vertexColors: true, side: THREE.DoubleSide, polygonOffset: true, polygonOffsetFactor: -2,
        polygonOffsetUnits: -2,
      });
      const colours = object.geometry.getAttribute('color');
      object.userData.islandColours = colours.array.slice();
      object.userData.tileColours = this.navmeshTileColours(object.geometry);
    } else {
      object = this.widenLines(object);
    }
    (this.layers[layer] = this.layers[layer] || []).push(object);
  }

  // Paths as 4-pixel lines drawn over the level (WebGL draws plain lines one pixel wide), in place of the
  // file's line segments.
  widenLines(lines) {
    const geometry = new LineSegmentsGeometry();
    geometry.setPositions(lines.geometry.getAttribute('position').array);
    const colours = lines.geometry.getAttribute('color');
    if (colours) {
      const rgb = [];
      for (let i = 0; i < colours.count; ++i) rgb.push(colours.getX(i), colours.getY(i), colours.getZ(i));
      geometry.setColors(rgb);
    }
    const material = new LineMaterial({ vertexColors: Boolean(colours), linewidth: 4, depthTest: false });
    material.resolution.set(window.innerWidth, window.innerHeight);
    this.lineMaterials = (this.lineMaterials || []).concat(material);
    const wide = new LineSegments2(geometry, material);
    wide.name = lines.name;
    wide.renderOrder = 10;
    wide.applyMatrix4(lines.matrixWorld);
    lines.visible = false;
    lines.parent.add(wide);
    return wide;
  }

  navmeshTileColours(geometry) {
    const positions = geometry.getAttribute('position');
    const colours = geometry.getAttribute('color');
    const size = colours.itemSize;
    const out = new Float32Array(colours.array.length);
    const index = geometry.getIndex();
    const tileSize = this.view.tiles ? this.view.tiles.size : 12.8;
    const [ox, , oz] = this.origin;
    const triangles = index ? index.count / 3 : positions.count / 3;
    for (let t = 0; t < triangles; ++t) {
      const corners = [0, 1, 2].map((k) => (index ? index.getX(3 * t + k) : 3 * t + k));
      let cx = 0;
      let cz = 0;
      for (const v of corners) {
        cx += positions.getX(v) / 3;
        cz += positions.getZ(v) / 3;
      }
      const colour = tileColour(Math.floor((cx + ox) / tileSize), Math.floor((cz + oz) / tileSize));
      for (const v of corners) {
        out[v * size] = colour.r;
        out[v * size + 1] = colour.g;
        out[v * size + 2] = colour.b;
        if (size === 4) out[v * size + 3] = 1;
      }
    }
    return out;
  }

  addTileBorders() {
    const tiles = this.view.tiles;
    if (!tiles || tiles.coords.length === 0) return;
    const positions = [];
    const s = tiles.size;
    // At the navmesh's usual height (the median), drawn over everything: a tile's state shows wherever
    // the level's walls and floors are.
    const [ox, oy, oz] = this.origin;
    const y = this.navmeshMedianHeight(tiles.y - oy) + 0.05;
    for (const [x, z] of tiles.coords) {
      const x0 = x * s - ox + 0.1;
      const x1 = (x + 1) * s - ox - 0.1;
      const z0 = z * s - oz + 0.1;
      const z1 = (z + 1) * s - oz - 0.1;
      positions.push(x0, y, z0, x1, y, z0, x1, y, z0, x1, y, z1, x1, y, z1, x0, y, z1, x0, y, z1, x0, y, z0);
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
    geometry.setAttribute('color', new THREE.Float32BufferAttribute(new Float32Array(positions.length), 3));
    const borders = new THREE.LineSegments(
      geometry, new THREE.LineBasicMaterial({ vertexColors: true, depthTest: false, transparent: true }));
    borders.renderOrder = 5;
    borders.name = 'tile_borders';
    this.scene.add(borders);
    this.layers.tiles = [borders];
  }

  navmeshMedianHeight(fallback) {
    const heights = [];
    for (const mesh of this.layers.navmesh || []) {
      const positions = mesh.geometry.getAttribute('position');
      for (let i = 0; i < positions.count; ++i) heights.push(positions.getY(i));
    }
    if (heights.length === 0) return fallback;
    heights.sort((a, b) => a - b);
    return heights[Math.floor(heights.length / 2)];
  }

  addBodies() {
    const geometries = this.view.shapes.map(shapeGeometry);
    const materials = {
      dynamic: new THREE.MeshLambertMaterial({ color: 0xc07a30 }),
      kinematic: new THREE.MeshLambertMaterial({ color: 0x4a7fd0 }),
      sensor: new THREE.MeshBasicMaterial({ color: 0xf0d040, transparent: true, opacity: 0.25, depthWrite: false }),
    };
    this.bodies = this.view.bodies.map((body) => {
      const material = body.sensor ? materials.sensor : materials[body.motion] || materials.dynamic;
      const mesh = new THREE.Mesh(geometries[body.shape], material);
      mesh.name = body.name || 'body';
      this.scene.add(mesh);
      return mesh;
    });
    this.layers.bodies = this.bodies;
  }

  // Each agent as a cylinder of its profile's size and colour, where the frame puts it (where it started when
  // the recording has no positions), and its target as a cone.
  addAgents() {
    const targetGeometry = new THREE.ConeGeometry(0.5, 1.2, 12);
    targetGeometry.rotateX(Math.PI);
    targetGeometry.translate(0, 0.6, 0);
    const targetMaterial = new THREE.MeshLambertMaterial({ color: 0xd030d0 });
    const materials = PROFILE_COLOURS.map((colour) => new THREE.MeshLambertMaterial({ color: colour }));
    this.agents = [];
    this.layers.agents = [];
    for (const agent of this.view.agents) {
      const radius = agent.radius || 0.6;
      const height = agent.height || 2.0;
      const geometry = new THREE.CylinderGeometry(radius, radius, height, 16);
      geometry.translate(0, height / 2, 0);
      const profile = agent.profile || 0;
      const body = new THREE.Mesh(geometry, materials[profile % materials.length]);
      body.position.fromArray(agent.position);
      body.userData.profile = profile;
      const target = new THREE.Mesh(targetGeometry, targetMaterial);
      target.position.fromArray(agent.target);
      target.userData.profile = profile;
      this.scene.add(body, target);
      this.agents.push(body);
      this.layers.agents.push(body, target);
    }
  }

  // Each character as its capsule at its feet of the frame, and the route it was sent along as a line.
  addCharacters() {
    const material = new THREE.MeshLambertMaterial({ color: 0x30d8e8 });
    this.characters = [];
    this.layers.characters = [];
    for (const character of this.view.characters || []) {
      const capsule = new THREE.CapsuleGeometry(character.radius, character.height - 2 * character.radius, 6, 16);
      capsule.translate(0, character.height / 2, 0);
      const mesh = new THREE.Mesh(capsule, material);
      mesh.name = character.name;
      this.scene.add(mesh);
      this.characters.push(mesh);
      this.layers.characters.push(mesh);
      if (character.route.length < 2) continue;
      const route = new THREE.Line(
        new THREE.BufferGeometry().setFromPoints(character.route.map((p) => new THREE.Vector3(p[0], p[1] + 0.1, p[2]))),
        new THREE.LineBasicMaterial({ color: 0x30d8e8, depthTest: false }));
      route.renderOrder = 8;
      this.scene.add(route);
      this.layers.characters.push(route);
    }
  }

  sceneBounds() {
    const box = new THREE.Box3();
    for (const layer of ['level', 'navmesh', 'bodies']) {
      for (const object of this.layers[layer] || []) box.expandByObject(object);
    }
    if (box.isEmpty()) box.setFromCenterAndSize(new THREE.Vector3(), new THREE.Vector3(10, 10, 10));
    return box;
  }

  frameCamera() {
    const box = this.sceneBounds();
    const centre = box.getCenter(new THREE.Vector3());
    const radius = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 1);
    this.camera.position.copy(centre).add(new THREE.Vector3(0.35, 0.95, 0.75).normalize().multiplyScalar(radius * 1.9));
    this.camera.near = radius / 1000;
    this.camera.far = radius * 100;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(centre);
    this.controls.update();
  }

  setupControls() {
    for (const input of document.querySelectorAll('input[data-layer]')) {
      const layer = input.dataset.layer;
      if (!this.layers[layer] || this.layers[layer].length === 0) input.parentElement.classList.add('empty');
      input.addEventListener('change', () => {
        this.applyVisibility();
        this.render();
      });
    }
    const chooser = document.getElementById('profile');
    this.profiles.forEach((profile, index) => {
      const option = document.createElement('option');
      option.value = String(index);
      option.textContent = profile.radius ? `${profile.name} (${profile.radius} m x ${profile.height} m)` : profile.name;
      chooser.appendChild(option);
    });
    if (this.profiles.length < 2) document.getElementById('profile-row').classList.add('empty');
    chooser.addEventListener('change', () => {
      this.showProfile(Number(chooser.value));
      this.showFrame(this.frame);
      this.render();
    });
    document.getElementById('colour-mode').addEventListener('change', (event) => {
      this.colourNavmesh(event.target.value);
      this.render();
    });
    const slider = document.getElementById('frame');
    slider.max = Math.max(this.view.frames.length - 1, 0);
    slider.addEventListener('input', () => {
      this.playing = false;
      this.showFrame(Number(slider.value));
      this.render();
    });
    document.getElementById('play').addEventListener('click', () => {
      this.playing = !this.playing;
      if (this.playing && this.frame >= this.view.frames.length - 1) this.showFrame(0);
      this.lastTick = performance.now();
      if (this.playing) requestAnimationFrame((now) => this.tick(now));
    });
    const legend = document.getElementById('legend');
    for (const state of TILE_STATES) {
      const entry = document.createElement('span');
      entry.innerHTML = `<i style="background:#${TILE_STATE_COLOURS[state].toString(16).padStart(6, '0')}"></i>${state}`;
      legend.appendChild(entry);
    }
  }

  // The layers the boxes tick, and of the navmesh and paths only the profile shown; agents of other profiles
  // stay, fainter.
  applyVisibility() {
    for (const input of document.querySelectorAll('input[data-layer]')) {
      const layer = input.dataset.layer;
      const perProfile = layer === 'navmesh' || layer === 'paths';
      for (const object of this.layers[layer] || [])
        object.visible = input.checked && (!perProfile || object.userData.profile === this.profile);
    }
    for (const object of this.layers.agents || []) {
      if (!object.userData.ownMaterial) {
        object.userData.ownMaterial = object.material;
        object.userData.fadedMaterial = object.material.clone();
        object.userData.fadedMaterial.transparent = true;
        object.userData.fadedMaterial.opacity = 0.35;
      }
      const own = object.userData.profile === this.profile;
      object.material = own ? object.userData.ownMaterial : object.userData.fadedMaterial;
    }
  }

  showProfile(index) {
    this.profile = index;
    document.getElementById('profile').value = String(index);
    this.applyVisibility();
    if (this.statsPublished) this.publishStats();
  }

  colourNavmesh(mode) {
    for (const mesh of this.layers.navmesh || []) {
      const colours = mesh.geometry.getAttribute('color');
      colours.array.set(mode === 'tile' ? mesh.userData.tileColours : mesh.userData.islandColours);
      colours.needsUpdate = true;
    }
  }

  tick(now) {
    if (!this.playing) return;
    const frames = this.view.frames;
    let next = this.frame;
    const elapsed = (now - this.lastTick) / 1000;
    // Advance through the recording at its own pace.
    while (next + 1 < frames.length && frames[next + 1].time - frames[this.frame].time <= elapsed) ++next;
    if (next !== this.frame) {
      this.lastTick = now;
      this.showFrame(next);
      this.render();
    }
    if (this.frame >= frames.length - 1) this.playing = false;
    else requestAnimationFrame((time) => this.tick(time));
  }

  showFrame(index) {
    const frames = this.view.frames;
    this.frame = index;
    document.getElementById('frame').value = index;
    if (frames.length === 0) {
      document.getElementById('time').textContent = 'no frames';
      return;
    }
    const frame = frames[index];
    document.getElementById('time').textContent =
      `step ${frame.step}, ${frame.time.toFixed(2)} s (frame ${index + 1} of ${frames.length})`;
    const poses = frame.poses;
    this.bodies.forEach((mesh, i) => {
      mesh.position.set(poses[7 * i], poses[7 * i + 1], poses[7 * i + 2]);
      mesh.quaternion.set(poses[7 * i + 4], poses[7 * i + 5], poses[7 * i + 6], poses[7 * i + 3]);
    });
    const feet = frame.characters || [];
    this.characters.forEach((mesh, i) => {
      if (3 * i + 2 < feet.length) mesh.position.set(feet[3 * i], feet[3 * i + 1], feet[3 * i + 2]);
    });
    const walkers = frame.agents || [];
    this.agents.forEach((mesh, i) => {
      if (3 * i + 2 < walkers.length) mesh.position.set(walkers[3 * i], walkers[3 * i + 1], walkers[3 * i + 2]);
    });
    const borders = this.layers.tiles && this.layers.tiles[0];
    if (borders && frame.tiles) {
      // The frame holds every profile's states, profile after profile; the shown profile's are drawn.
      const count = this.view.tiles.coords.length;
      const colours = borders.geometry.getAttribute('color');
      const colour = new THREE.Color();
      for (let tile = 0; tile < count; ++tile) {
        const state = frame.tiles[this.profile * count + tile];
        colour.setHex(TILE_STATE_COLOURS[TILE_STATES[state]] || 0xffffff);
        for (let v = 0; v < 8; ++v) colours.setXYZ(tile * 8 + v, colour.r, colour.g, colour.b);
      }
      colours.needsUpdate = true;
    }
    if (this.statsPublished) this.publishStats();
  }

  resize() {
    this.camera.aspect = window.innerWidth / window.innerHeight;
    this.camera.updateProjectionMatrix();
    this.renderer.setSize(window.innerWidth, window.innerHeight);
    for (const material of this.lineMaterials || []) material.resolution.set(window.innerWidth, window.innerHeight);
    this.render();
  }

  render() {
    this.renderer.render(this.scene, this.camera);
  }

  // What the browser test reads: how much the page loaded and drew.
  publishStats() {
    let objects = 0;
    let triangles = 0;
    this.scene.traverse((object) => {
      if (!object.visible || (!object.isMesh && !object.isLine)) return;
      ++objects;
      if (object.isMesh && !object.isLineSegments2) {
        const index = object.geometry.getIndex();
        triangles += (index ? index.count : object.geometry.getAttribute('position').count) / 3;
      }
    });
    const byProfile = this.profiles.map(() => 0);
    for (const mesh of this.layers.navmesh || []) {
      const index = mesh.geometry.getIndex();
      byProfile[mesh.userData.profile] += (index ? index.count : mesh.geometry.getAttribute('position').count) / 3;
    }
    const stats = {
      ready: true,
      objects,
      triangles,
      navmesh_triangles: byProfile[this.profile],
      navmesh_triangles_by_profile: byProfile,
      profiles: this.profiles.map((profile) => profile.name),
      profile: this.profile,
      frame: this.frame,
      agent_positions: this.agents.map((mesh) => [mesh.position.x, mesh.position.y, mesh.position.z]),
      level_objects: (this.layers.level || []).length,
      path_objects: (this.layers.paths || []).length,
      bodies: this.bodies.length,
      agents: this.agents.length,
      characters: this.characters.length,
      character_feet: this.characters.map((mesh) => [mesh.position.x, mesh.position.y, mesh.position.z]),
      tiles: this.view.tiles ? this.view.tiles.coords.length : 0,
      frames: this.view.frames.length,
      drawn_triangles: this.renderer.info.render.triangles,
      navmesh_colours: this.view.navmesh_colours || [],
      origin: this.origin,
    };
    document.getElementById('stats').textContent = JSON.stringify(stats);
    document.body.dataset.ready = '1';
    this.statsPublished = true;
  }
}

async function main() {
  const view = window.STRATA_VIEW;
  const status = document.getElementById('stats');
  if (!view) {
    status.textContent = JSON.stringify({ ready: false, error: 'data.js did not load' });
    return;
  }
  document.getElementById('title').textContent = view.title;
  try {
    const viewer = new Viewer(view, window.STRATA_GLB ? decodeBase64(window.STRATA_GLB) : null);
    await viewer.load();
  } catch (error) {
    status.textContent = JSON.stringify({ ready: false, error: String(error) });
    throw error;
  }
}

main();
