// The 3D view: the map's OctoMap (its occupied voxel centres, GET .../octomap?format=pcd_binary) and keyframe point
// clouds in the map frame (GET .../keyframes/{kf}/cloud?format=pcd_binary&frame=map), drawn with WebGL as points.
// REP-103: x forward, y left, z up [m]. Drag to orbit, wheel to zoom. Voxels are coloured by height, clouds orange.
'use strict';

const Pcd = {
  // The xyz of a PCD file (DATA ascii or binary; any float32 fields besides x, y, z are skipped).
  parse(buffer) {
    const bytes = new Uint8Array(buffer);
    let pos = 0, header = {};
    for (;;) {
      let end = bytes.indexOf(10, pos);
      if (end < 0) end = bytes.length;
      const line = new TextDecoder().decode(bytes.subarray(pos, end)).trim();
      pos = end + 1;
      if (!line || line[0] === '#') { if (pos >= bytes.length) break; continue; }
      const [key, ...values] = line.split(/\s+/);
      header[key] = values;
      if (key === 'DATA' || pos >= bytes.length) break;
    }
    const fields = header.FIELDS || [], sizes = (header.SIZE || []).map(Number);
    const counts = (header.COUNT || fields.map(() => '1')).map(Number);
    const n = Number((header.POINTS || [0])[0]);
    const mode = (header.DATA || ['ascii'])[0];
    const out = new Float32Array(3 * n);
    const index = ['x', 'y', 'z'].map(f => fields.indexOf(f));
    if (index.some(i => i < 0)) throw new Error('PCD without x y z fields');
    if (mode === 'binary') {
      const offset = [], stride = fields.reduce((s, f, i) => { offset.push(s); return s + sizes[i] * counts[i]; }, 0);
      const view = new DataView(buffer, pos);
      for (let p = 0; p < n; ++p) for (let k = 0; k < 3; ++k) out[3 * p + k] = view.getFloat32(p * stride + offset[index[k]], true);
    } else if (mode === 'ascii') {
      const lines = new TextDecoder().decode(bytes.subarray(pos)).split('\n').filter(l => l.trim());
      for (let p = 0; p < n; ++p) { const v = lines[p].trim().split(/\s+/); for (let k = 0; k < 3; ++k) out[3 * p + k] = Number(v[index[k]]); }
    } else {
      throw new Error('PCD DATA ' + mode + ' is not read here (ask for format=pcd_binary)');
    }
    return out;
  },
};

// Column-major 4x4 matrices, as WebGL wants them.
const Mat4 = {
  mul(a, b) {
    const o = new Float32Array(16);
    for (let c = 0; c < 4; ++c) for (let r = 0; r < 4; ++r) {
      let s = 0;
      for (let k = 0; k < 4; ++k) s += a[k * 4 + r] * b[c * 4 + k];
      o[c * 4 + r] = s;
    }
    return o;
  },
  perspective(fovy_rad, aspect, near, far) {
    const f = 1 / Math.tan(fovy_rad / 2), o = new Float32Array(16);
    o[0] = f / aspect; o[5] = f; o[10] = (far + near) / (near - far); o[11] = -1; o[14] = 2 * far * near / (near - far);
    return o;
  },
  lookAt(eye, at, up) {
    const sub = (a, b) => a.map((v, i) => v - b[i]);
    const norm = v => { const l = Math.hypot(...v) || 1; return v.map(x => x / l); };
    const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
    const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    const f = norm(sub(at, eye)), s = norm(cross(f, up)), u = cross(s, f);
    return new Float32Array([s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0,
                             -dot(s, eye), -dot(u, eye), dot(f, eye), 1]);
  },
};

// A WebGL canvas drawing point sets: add(name, xyz, rgb, size_m or null for a fixed pixel size).
class PointScene {
  constructor(canvas) {
    this.canvas = canvas;
    const gl = this.gl = canvas.getContext('webgl', { preserveDrawingBuffer: true, antialias: false });
    if (!gl) throw new Error('this browser offers no WebGL');
    const shader = (type, src) => {
      const s = gl.createShader(type);
      gl.shaderSource(s, src); gl.compileShader(s);
      if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
      return s;
    };
    const p = this.program = gl.createProgram();
    gl.attachShader(p, shader(gl.VERTEX_SHADER, `
      attribute vec3 position; attribute vec3 colour; uniform mat4 mvp; uniform float size_m, px_per_m, size_px;
      varying vec3 c;
      void main() {
        gl_Position = mvp * vec4(position, 1.0);
        gl_PointSize = size_m > 0.0 ? clamp(px_per_m * size_m / gl_Position.w, 1.0, 48.0) : size_px;
        c = colour;
      }`));
    gl.attachShader(p, shader(gl.FRAGMENT_SHADER, 'precision mediump float; varying vec3 c; void main() { gl_FragColor = vec4(c, 1.0); }'));
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(p));
    this.sets = [];
    this.yaw = -2.2; this.pitch = 0.6; this.distance = 6; this.centre = [0, 0, 0];
    let drag = null;
    canvas.addEventListener('mousedown', e => { drag = [e.clientX, e.clientY]; });
    window.addEventListener('mouseup', () => { drag = null; });
    canvas.addEventListener('mousemove', e => {
      if (!drag) return;
      this.yaw -= (e.clientX - drag[0]) * 0.01;
      this.pitch = Math.max(-1.5, Math.min(1.5, this.pitch + (e.clientY - drag[1]) * 0.01));
      drag = [e.clientX, e.clientY];
      this.draw();
    });
    canvas.addEventListener('wheel', e => { e.preventDefault(); this.distance *= Math.exp(e.deltaY * 0.001); this.draw(); }, { passive: false });
  }
  clear() {
    for (const s of this.sets) { this.gl.deleteBuffer(s.position); this.gl.deleteBuffer(s.colour); }
    this.sets = [];
  }
  // xyz: Float32Array of n points (non-finite ones skipped); rgb(x, y, z) -> [r, g, b] in [0, 1]. Returns n drawn.
  add(xyz, rgb, size_m) {
    const gl = this.gl;
    const keep = [];
    for (let i = 0; i < xyz.length; i += 3) if (isFinite(xyz[i]) && isFinite(xyz[i + 1]) && isFinite(xyz[i + 2])) keep.push(i);
    const pos = new Float32Array(3 * keep.length), col = new Float32Array(3 * keep.length);
    keep.forEach((i, j) => {
      pos.set(xyz.subarray(i, i + 3), 3 * j);
      col.set(rgb(xyz[i], xyz[i + 1], xyz[i + 2]), 3 * j);
    });
    const buffer = data => { const b = gl.createBuffer(); gl.bindBuffer(gl.ARRAY_BUFFER, b); gl.bufferData(gl.ARRAY_BUFFER, data, gl.STATIC_DRAW); return b; };
    this.sets.push({ position: buffer(pos), colour: buffer(col), n: keep.length, size_m: size_m || 0 });
    return keep.length;
  }
  // Looks at the middle of a box [min, max] from far enough to see all of it.
  frame(min, max) {
    this.centre = [0, 1, 2].map(k => (min[k] + max[k]) / 2);
    this.distance = Math.max(1, 1.1 * Math.hypot(max[0] - min[0], max[1] - min[1], max[2] - min[2]));
  }
  draw() {
    const gl = this.gl, c = this.canvas, fovy = 50 * Math.PI / 180;
    gl.viewport(0, 0, c.width, c.height);
    gl.clearColor(0.07, 0.09, 0.13, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    const eye = [this.centre[0] + this.distance * Math.cos(this.pitch) * Math.cos(this.yaw),
                 this.centre[1] + this.distance * Math.cos(this.pitch) * Math.sin(this.yaw),
                 this.centre[2] + this.distance * Math.sin(this.pitch)];
    const mvp = Mat4.mul(Mat4.perspective(fovy, c.width / c.height, 0.05, 200), Mat4.lookAt(eye, this.centre, [0, 0, 1]));
    gl.useProgram(this.program);
    gl.uniformMatrix4fv(gl.getUniformLocation(this.program, 'mvp'), false, mvp);
    gl.uniform1f(gl.getUniformLocation(this.program, 'px_per_m'), c.height / (2 * Math.tan(fovy / 2)));
    gl.uniform1f(gl.getUniformLocation(this.program, 'size_px'), 1.5);
    for (const s of this.sets) {
      gl.uniform1f(gl.getUniformLocation(this.program, 'size_m'), s.size_m);
      for (const [name, b] of [['position', s.position], ['colour', s.colour]]) {
        const at = gl.getAttribLocation(this.program, name);
        gl.bindBuffer(gl.ARRAY_BUFFER, b);
        gl.enableVertexAttribArray(at);
        gl.vertexAttribPointer(at, 3, gl.FLOAT, false, 0, 0);
      }
      gl.drawArrays(gl.POINTS, 0, s.n);
    }
  }
  // Pixels whose colour is not the background's (what the last draw put on the canvas).
  litPixels() {
    const gl = this.gl, c = this.canvas, d = new Uint8Array(4 * c.width * c.height);
    gl.readPixels(0, 0, c.width, c.height, gl.RGBA, gl.UNSIGNED_BYTE, d);
    let n = 0;
    for (let i = 0; i < d.length; i += 4) if (Math.abs(d[i] - 18) + Math.abs(d[i + 1] - 23) + Math.abs(d[i + 2] - 33) > 6) ++n;
    return n;
  }
}

async function fetchCloud(path) {
  const r = await fetch(path, { headers: Api.headers() });
  if (!r.ok) {
    let e = {};
    try { e = (await r.json()).error || {}; } catch (x) { /* not JSON */ }
    throw new ApiError(r.status, e);
  }
  return { xyz: Pcd.parse(await r.arrayBuffer()), served: Number(r.headers.get('X-Points')) };
}

// ---- 3D: OctoMap and keyframe clouds ----------------------------------------------------------------------------
Console.views.view3d = {
  scene: null,
  async show() {
    const box = $('#view3d');
    if (!this.scene) {
      const canvas = el('canvas', { id: 'view3d-canvas', width: '960', height: '640' });
      box.replaceChildren(Images.figure(canvas, el('span', { id: 'view3d-caption' })));
      this.scene = new PointScene(canvas);
    }
    let tree = null;
    try { tree = await Api.get(M() + '/octomap?format=json'); } catch (e) { if (e.status !== 404) throw e; }
    const scenes = (await Api.get(M() + '/scenes?limit=100')).scenes;
    const keyframes = [];
    for (const s of scenes) for (const k of (await Api.get(M() + '/scenes/' + s.id)).keyframes || []) keyframes.push({ scene: s.id, ...k });
    keyframes.sort((a, b) => a.id - b.id);
    const list = $('#view3d-keyframes');
    const checked = new Set([...list.querySelectorAll('input:checked')].map(i => Number(i.value)));
    if (!checked.size && keyframes.length) checked.add(keyframes[0].id);
    list.replaceChildren(...keyframes.map(k => el('label', {}, el('input', Object.assign({ type: 'checkbox', value: String(k.id) },
      checked.has(k.id) ? { checked: '' } : {})), ' ' + k.kind + ' ' + k.id + ' (scene ' + k.scene + ')')));
    for (const i of list.querySelectorAll('input')) i.addEventListener('change', () => this.show().catch(Console.fail));
    await this.draw(tree, keyframes.filter(k => checked.has(k.id)).map(k => k.id));
  },
  async draw(tree, keyframeIds) {
    const scene = this.scene, canvas = scene.canvas;
    scene.clear();
    let voxels = 0, points = 0;
    // Framed on where most of the points are (2 % and 98 % per axis of a sample): a few far rays do not shrink the view.
    const sample = [[], [], []];
    const grow = xyz => {
      const step = 3 * Math.max(1, Math.floor(xyz.length / 3 / 20000));
      for (let i = 0; i + 2 < xyz.length; i += step) {
        if (isFinite(xyz[i]) && isFinite(xyz[i + 1]) && isFinite(xyz[i + 2])) for (let k = 0; k < 3; ++k) sample[k].push(xyz[i + k]);
      }
    };
    const clouds = [];
    for (const id of keyframeIds) clouds.push(await fetchCloud(M() + '/keyframes/' + id + '/cloud?format=pcd_binary&frame=map'));
    for (const c of clouds) {
      grow(c.xyz);  // framed on the chosen keyframes when there are any, else on the whole tree
      points += scene.add(c.xyz, () => [0.98, 0.62, 0.2], null);
    }
    if (tree && $('#view3d-voxels').checked) {
      const v = await fetchCloud(M() + '/octomap?format=pcd_binary');
      if (!clouds.length) grow(v.xyz);
      const z0 = tree.bbox ? tree.bbox.min[2] : 0, z1 = tree.bbox ? tree.bbox.max[2] : 1;
      voxels = scene.add(v.xyz, (x, y, z) => Images.colour((z - z0) / Math.max(1e-6, z1 - z0)).map(k => k / 255), tree.resolution_m);
    }
    if (sample[0].length) {
      const q = (a, f) => a[Math.min(a.length - 1, Math.floor(f * a.length))];
      for (const a of sample) a.sort((x, y) => x - y);
      scene.frame(sample.map(a => q(a, 0.02)), sample.map(a => q(a, 0.98)));
    }
    scene.draw();
    canvas.dataset.voxels = voxels;
    canvas.dataset.points = points;
    canvas.dataset.keyframes = keyframeIds.join(',');
    canvas.dataset.litPixels = scene.litPixels();
    $('#view3d-caption').textContent = (tree ? voxels.toLocaleString('en') + ' occupied voxels of the OctoMap (resolution ' +
      tree.resolution_m + ' m, coloured by height), ' : 'this map has no OctoMap; ') + points.toLocaleString('en') +
      ' points of keyframe' + (keyframeIds.length === 1 ? ' ' : 's ') + (keyframeIds.join(', ') || 'none') + ' (orange). Drag to orbit, wheel to zoom.';
  },
};
$('#view3d-voxels').addEventListener('change', () => Console.views.view3d.show().catch(Console.fail));
