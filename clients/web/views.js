// The console's views: each reads the routes it shows (GET only) and offers the edits its role may make.
'use strict';

const M = () => '/v1/maps/' + encodeURIComponent(Console.map);
const kv = obj => el('table', { class: 'kv' }, ...Object.entries(obj).map(([k, v]) =>
  el('tr', {}, el('td', {}, k), el('td', {}, typeof v === 'object' && v !== null ? JSON.stringify(v) : String(v)))));
const pre = obj => el('pre', {}, JSON.stringify(obj, null, 1));
const geometryOf = (layer, bitmap) => {
  const g = layer.geometry || {};
  return { resolution: g.resolution_m || layer.resolution || 0.05, origin: g.origin || layer.origin || [0, 0, 0], height: bitmap.height };
};
// The first occupancy (else any) layer as a floor plan; shared by the where-is marker and the furniture graphs.
async function floorPlan() {
  const layers = (await Api.get(M() + '/layers')).layers;
  const pick = layers.find(l => l.kind === 'occupancy') || layers[0];
  if (!pick) return null;
  const layer = await Api.get(M() + '/layers/' + encodeURIComponent(pick.name) + '?format=json');
  const bitmap = await Api.bitmap(M() + '/layers/' + encodeURIComponent(pick.name) + '?format=png');
  const canvas = Images.canvasOf(bitmap);
  return { canvas, geo: geometryOf(layer, bitmap), name: pick.name };
}
// The pixel rectangle of a map-frame box (centre, extent [m]) seen by a scene's camera (pose of the optical frame in
// the map frame, pinhole intrinsics), or null when it is behind the camera.
function projectBox(scene, centre, extent) {
  const [qx, qy, qz, qw] = scene.pose.orientation, t = scene.pose.position, k = scene.camera;
  const R = [[1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
             [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
             [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)]];
  let u0 = Infinity, v0 = Infinity, u1 = -Infinity, v1 = -Infinity;
  for (let c = 0; c < 8; ++c) {
    const p = [0, 1, 2].map(i => centre[i] + ((c >> i) & 1 ? 0.5 : -0.5) * extent[i] - t[i]);
    const q = [0, 1, 2].map(j => R[0][j] * p[0] + R[1][j] * p[1] + R[2][j] * p[2]);  // R^T (p - t)
    if (q[2] <= 0.05) return null;
    const u = k.fx * q[0] / q[2] + k.cx, v = k.fy * q[1] / q[2] + k.cy;
    u0 = Math.min(u0, u); v0 = Math.min(v0, v); u1 = Math.max(u1, u); v1 = Math.max(v1, v);
  }
  return [u0, v0, u1 - u0, v1 - v0];
}
async function keyframeFigure(id, role, outline) {
  const kf = Api.bitmap(M() + '/keyframes/' + id + '/depth');
  const bg = Api.bitmap(M() + '/keyframes/' + id + '/background');
  const [d, b] = await Promise.all([kf, bg]);
  const box = el('div', { class: 'strip' });
  const depth = Images.depthCanvas(d), background = Images.depthCanvas(b);
  if (outline) {
    for (const c of [depth, background]) {
      const ctx = c.getContext('2d');
      ctx.strokeStyle = '#ff2d55'; ctx.lineWidth = 3;
      ctx.strokeRect(...outline);
      c.dataset.outline = outline.map(Math.round).join(',');
    }
  }
  box.append(Images.figure(depth, 'keyframe ' + id + (role ? ' (' + role + ')' : '') + ' depth'),
             Images.figure(background, 'background'));
  return box;
}

// A label layer's categories: each with its colour (the server's PNG palette, engine/grid/render.cc), its id and name,
// the cells the API counts and the cells of that colour in the image (canvas.dataset.pixelsPerLabel).
const labelColour = id => [60 + (id * 151) % 180, 60 + (id * 57) % 180, 60 + (id * 97) % 180];
function labelLegend(canvas, meta) {
  const cells = (meta.statistics && meta.statistics.cells_per_label) || {};
  const d = Images.pixels(canvas).data, seen = {};
  const entries = Object.entries(meta.labels || {}).map(([id, name]) => [Number(id), name]);
  for (let i = 0; i < d.length; i += 4) {
    for (const [id] of entries) {
      const [r, g, b] = labelColour(id);
      if (d[i] === r && d[i + 1] === g && d[i + 2] === b) { seen[id] = (seen[id] || 0) + 1; break; }
    }
  }
  canvas.dataset.pixelsPerLabel = JSON.stringify(Object.fromEntries(entries.map(([id]) => [id, seen[id] || 0])));
  const swatch = id => { const s = el('span', { class: 'swatch' }); s.style.background = 'rgb(' + labelColour(id).join(',') + ')'; return s; };
  return el('table', { class: 'kv categories' }, el('tr', {}, el('th', {}, ''), el('th', {}, 'category'), el('th', {}, 'cells')),
    ...entries.map(([id, name]) => el('tr', { 'data-label': String(id) }, el('td', {}, swatch(id)), el('td', {}, id + ' ' + name),
      el('td', {}, String(cells[id] ?? 0)))));
}

// ---- Map: layers as images -------------------------------------------------------------------------------------
Console.views.layers = {
  async show() {
    const box = $('#layers');
    box.replaceChildren();
    const layers = (await Api.get(M() + '/layers')).layers;
    const agents = (await Api.get(M() + '/agents')).agents || [];
    const form = $('#viewpoint-form');
    form.agent.replaceChildren(...agents.map(a => el('option', {}, a.id || a.agent)));
    form.layer.replaceChildren(...layers.filter(l => l.kind === 'probability').map(l => el('option', {}, l.name)));
    for (const l of layers) {
      const meta = await Api.get(M() + '/layers/' + encodeURIComponent(l.name) + '?format=json&statistics=true');
      const bitmap = await Api.bitmap(M() + '/layers/' + encodeURIComponent(l.name) + '?format=png');
      const canvas = l.kind === 'probability' ? Images.probabilityCanvas(bitmap) : Images.canvasOf(bitmap);
      canvas.dataset.layer = l.name;
      canvas.dataset.kind = l.kind;
      canvas.style.width = Math.min(480, canvas.width * 4) + 'px';
      const caption = el('div', {}, el('b', {}, l.name), ' ' + l.kind + ' ' + bitmap.width + 'x' + bitmap.height);
      if (l.kind === 'probability') {
        caption.append(Images.legend('p'));
        const geo = geometryOf(meta, bitmap);
        canvas._geo = geo;
        const regions = (await Api.get(M() + '/layers/' + encodeURIComponent(l.name) + '/regions')).regions;
        const ctx = canvas.getContext('2d');
        ctx.strokeStyle = '#ff2d55';
        ctx.lineWidth = 1;
        for (const r of regions) {
          ctx.beginPath();
          r.polygon.forEach((p, i) => { const [x, y] = Images.toPixel(geo, p[0], p[1]); i ? ctx.lineTo(x, y) : ctx.moveTo(x, y); });
          ctx.closePath();
          ctx.stroke();
        }
        caption.append(el('div', {}, regions.length + ' regions outlined'));
        canvas.dataset.regions = regions.length;
        ctx.fillStyle = '#ffffff';
        for (const a of agents) {
          const [x, y] = Images.toPixel(geo, a.position[0], a.position[1]);
          ctx.beginPath(); ctx.arc(x, y, 3, 0, 2 * Math.PI); ctx.fill();
          ctx.beginPath(); ctx.moveTo(x, y);
          ctx.lineTo(x + 8 * Math.cos(a.heading_rad), y - 8 * Math.sin(a.heading_rad)); ctx.strokeStyle = '#fff'; ctx.stroke();
          try {
            const att = await Api.get(M() + '/attention?agent=' + encodeURIComponent(a.id || a.agent) + '&layer=' + encodeURIComponent(l.name));
            caption.append(el('div', {}, 'agent "' + (a.id || a.agent) + '"' + (att.attending ? ' attends region ' + att.region.id : ' attends nothing')));
          } catch (e) { /* no attention for this layer */ }
        }
      }
      if (l.kind === 'label') caption.append(labelLegend(canvas, meta));
      if (l.kind === 'occupancy' && meta.statistics) caption.append(kv(meta.statistics));
      box.append(Images.figure(canvas, caption));
    }
    if (!layers.length) box.append('This map has no layers.');
    try {
      $('#octomap-info').replaceChildren(kv(await Api.get(M() + '/octomap?format=json')));
    } catch (e) {
      $('#octomap-info').textContent = e.status === 404 ? 'This map has no OctoMap.' : e.message;
    }
  },
};
$('#octomap-clear').addEventListener('submit', async ev => {
  ev.preventDefault();
  const f = ev.target;
  try {
    const r = await Api.post(M() + '/octomap:clear', { min: f.min.value.split(',').map(Number), max: f.max.value.split(',').map(Number) });
    Console.status('OctoMap box cleared: ' + JSON.stringify(r));
    await Console.views.layers.show();
  } catch (e) { Console.fail(e); }
});
$('#viewpoint-form').addEventListener('submit', async ev => {
  ev.preventDefault();
  const f = ev.target;
  try {
    const r = await Api.post(M() + '/viewpoints', { robot: f.robot.value.split(',').map(Number), agent: f.agent.value, layer: f.layer.value });
    $('#viewpoints').replaceChildren(el('table', { class: 'table', id: 'viewpoint-table' }, el('tr', {}, el('th', {}, 'rank'),
      el('th', {}, 'position [m]'), el('th', {}, 'score'), el('th', {}, 'relation')),
      ...r.viewpoints.map(v => el('tr', {}, el('td', {}, String(v.rank)), el('td', {}, fmtVec(v.position)),
        el('td', {}, v.score.toFixed(3)), el('td', {}, v.relation)))));
    // The ranked viewpoints on the layer's image: numbered, facing their yaw.
    const canvas = document.querySelector('#layers canvas[data-layer="' + f.layer.value + '"]');
    if (canvas && canvas._geo) {
      const ctx = canvas.getContext('2d');
      ctx.fillStyle = '#ff9500'; ctx.strokeStyle = '#ff9500'; ctx.font = '8px sans-serif';
      for (const v of r.viewpoints) {
        const [x, y] = Images.toPixel(canvas._geo, v.position[0], v.position[1]);
        ctx.beginPath(); ctx.arc(x, y, 2, 0, 2 * Math.PI); ctx.fill();
        ctx.beginPath(); ctx.moveTo(x, y); ctx.lineTo(x + 6 * Math.cos(v.yaw_rad), y - 6 * Math.sin(v.yaw_rad)); ctx.stroke();
        ctx.fillText(String(v.rank), x + 3, y - 3);
      }
    }
  } catch (e) { Console.fail(e); }
});

// ---- Events ------------------------------------------------------------------------------------------------------
Console.views.events = {
  cursors: [0],
  query() {
    const f = $('#event-filter');
    const q = new URLSearchParams({ limit: '50' });
    for (const k of ['type', 'instance', 'since', 'until']) if (f[k].value.trim()) q.set(k, f[k].value.trim());
    return q;
  },
  async show(after) {
    const t0 = performance.now();
    const q = this.query();
    q.set('after', String(after || 0));
    const page = await Api.get(M() + '/events?' + q);
    this.next = page.next_after;
    const tbody = $('#event-table tbody');
    tbody.replaceChildren(...page.events.map(e => this.row(e)));
    $('#events-page').textContent = page.events.length + ' events after id ' + (after || 0) + (this.next ? '' : ' (last page)');
    $('#events-next').disabled = !this.next;
    const tl = $('#timeline');
    tl.replaceChildren();
    if (page.events.length) {
      // Ids are not in time order: the scale spans the page's earliest and latest stamps.
      const stamps = page.events.map(e => Number(e.stamp_ns));
      const lo = Math.min(...stamps), hi = Math.max(...stamps);
      page.events.forEach((e, i) => {
        const x = hi > lo ? (stamps[i] - lo) / (hi - lo) : 0.5;
        tl.append(el('span', { class: 't-' + e.type, style: 'left:' + (x * 99).toFixed(2) + '%', title: e.type + ' ' + e.id }));
      });
    }
    document.body.dataset.eventsMs = (performance.now() - t0).toFixed(1);  // this page's request and drawing
    document.body.dataset.eventsLoadedAt = performance.now().toFixed(1);    // since navigation start
  },
  row(e) {
    return el('tr', { 'data-event': e.id, onclick: () => this.open(e.id) }, el('td', {}, String(e.id)), el('td', {}, fmtTime(e.stamp_ns)),
      el('td', {}, e.type), el('td', {}, e.detection), el('td', {}, e.instance === null ? '' : String(e.instance)),
      el('td', {}, e.label || ''), el('td', {}, e.explanation));
  },
  async open(id) {
    for (const tr of document.querySelectorAll('#event-table tr')) tr.classList.toggle('selected', Number(tr.dataset.event) === id);
    const e = await Api.get(M() + '/events/' + id);
    const box = $('#event-detail');
    const edit = el('form', { class: 'inline edit' }, el('input', { name: 'label', placeholder: 'new label', size: '14' }),
      el('button', {}, 'relabel (operator)'));
    edit.addEventListener('submit', async ev => {
      ev.preventDefault();
      try {
        await Api.post(M() + '/events/' + id + ':label', { label: edit.label.value, source: 'operator' });
        Console.status('event ' + id + ' relabelled');
        await this.open(id);
      } catch (x) { Console.fail(x); }
    });
    // An operator removes a wrong event (admin; audited as event.delete): gone from the list, its keyframes stay.
    const del = el('button', { id: 'delete-event', class: 'edit admin-only', onclick: async () => {
      if (!confirm('Delete event ' + id + '?')) return;
      try {
        await Api.del(M() + '/events/' + id);
        Console.status('event ' + id + ' deleted');
        box.replaceChildren();
        await this.show(this.cursors[this.cursors.length - 1]);
      } catch (x) { Console.fail(x); }
    } }, 'delete event');
    box.replaceChildren(el('h3', {}, e.type + ' event ' + id), el('p', {}, e.explanation), kv({ time: fmtTime(e.stamp_ns),
      detection: e.detection, instance: e.instance, label: e.label, scene: e.scene }), edit, del);
    Console.applyRole();  // before the evidence loads: no moment where a reader sees the edit controls
    if (e.details && e.details.segment) box.append(el('p', {}, 'segment: centroid ' + fmtVec(e.details.segment.centroid_m) +
      ' m, extent ' + fmtVec(e.details.segment.extent_m) + ' m, ' + e.details.segment.points + ' points'));
    let outline = null;
    if (e.details && e.details.segment && e.scene !== null) {
      const scene = await Api.get(M() + '/scenes/' + e.scene);
      outline = projectBox(scene, e.details.segment.centroid_m, e.details.segment.extent_m);
    }
    for (const k of e.evidence || []) box.append(await keyframeFigure(k.keyframe, k.role, outline));
    Console.applyRole();
  },
  onMessage(kind, data) {
    if ((kind === 'change' || kind === 'label') && Console.view === 'events' && !this.next) {
      const tbody = $('#event-table tbody');
      if (!tbody.querySelector('[data-event="' + data.id + '"]')) tbody.append(this.row(data));
    }
  },
};
$('#event-filter').addEventListener('submit', ev => { ev.preventDefault(); Console.views.events.cursors = [0]; Console.views.events.show(0).catch(Console.fail); });
$('#events-first').addEventListener('click', () => { Console.views.events.cursors = [0]; Console.views.events.show(0).catch(Console.fail); });
$('#events-next').addEventListener('click', () => { const v = Console.views.events; v.cursors.push(v.next); v.show(v.next).catch(Console.fail); });

// ---- Instances and where-is ---------------------------------------------------------------------------------------
Console.views.instances = {
  async show() {
    const page = await Api.get(M() + '/instances?limit=1000');
    $('#instance-table tbody').replaceChildren(...page.instances.map(i => el('tr', { 'data-instance': i.id, onclick: () => this.open(i.id) },
      el('td', {}, String(i.id)), el('td', {}, i.kind), el('td', {}, i.status), el('td', { class: 'label' }, topLabel(i.labels) + (i.label_locked ? ' (operator)' : '')),
      el('td', {}, fmtVec(i.position_m)), el('td', {}, i.pinned ? 'pinned' : ''))));
    if (this.selected) await this.open(this.selected);
  },
  async open(id) {
    this.selected = id;
    for (const tr of document.querySelectorAll('#instance-table tr')) tr.classList.toggle('selected', Number(tr.dataset.instance) === id);
    const h = await Api.get(M() + '/instances/' + id + '/history');
    const i = h.instance;
    const relabel = el('form', { class: 'inline edit', id: 'relabel-form' }, el('input', { name: 'label', placeholder: 'new label', size: '14' }),
      el('button', { id: 'relabel' }, 'relabel (operator)'));
    relabel.addEventListener('submit', ev => { ev.preventDefault(); this.edit('POST', '/instances/' + id + ':label', { label: relabel.label.value, source: 'operator' }, id); });
    const actions = el('div', { class: 'inline edit' },
      el('button', { id: 'pin', onclick: () => this.edit('POST', '/instances/' + id + (i.pinned ? ':unpin' : ':pin'), {}, id) }, i.pinned ? 'unpin' : 'pin'),
      el('button', { id: 'delete', class: 'edit admin-only', onclick: () => { if (confirm('Delete instance ' + id + '?')) this.edit('DELETE', '/instances/' + id, undefined, id); } }, 'delete'));
    $('#instance-detail').replaceChildren(el('h3', {}, i.kind + ' ' + id + ' (' + i.status + ')'),
      kv({ labels: i.labels, label_locked: i.label_locked, pinned: i.pinned, position_m: fmtVec(i.position_m), extent_m: fmtVec(i.extent_m),
           last_seen: fmtTime(i.last_seen_ns) }), relabel, actions, el('h4', {}, 'history'),
      el('table', { class: 'table' }, el('tr', {}, el('th', {}, 'time'), el('th', {}, 'present'), el('th', {}, 'position [m]'), el('th', {}, 'event')),
        ...h.history.map(x => el('tr', {}, el('td', {}, fmtTime(x.stamp_ns)), el('td', {}, x.present ? 'present' : 'gone'),
          el('td', {}, fmtVec(x.position_m)), el('td', {}, x.event === null ? '' : String(x.event))))));
    Console.applyRole();
  },
  async edit(method, path, body, id) {
    try {
      if (method === 'DELETE') await Api.del(M() + path); else await Api.post(M() + path, body);
      $('#where-answer').replaceChildren();  // its sentence may name the old label or a deleted instance
      Console.status('instance ' + id + ': done');
      await this.show();
    } catch (e) { Console.fail(e); }
  },
};
$('#where-form').addEventListener('submit', async ev => {
  ev.preventDefault();
  const box = $('#where-answer');
  try {
    const a = await Api.get(M() + '/where?label=' + encodeURIComponent(ev.target.label.value));
    box.replaceChildren(el('div', { class: 'sentence' }, a.sentence));
    const plan = await floorPlan();
    if (plan && a.position_m) {
      const ctx = plan.canvas.getContext('2d');
      const [x, y] = Images.toPixel(plan.geo, a.position_m[0], a.position_m[1]);
      ctx.strokeStyle = '#e11d48'; ctx.lineWidth = 2;
      ctx.beginPath(); ctx.arc(x, y, 6, 0, 2 * Math.PI); ctx.stroke();
      plan.canvas.id = 'where-map';
      plan.canvas.style.width = Math.min(480, plan.canvas.width * 4) + 'px';
      box.append(Images.figure(plan.canvas, 'marker: ' + fmtVec(a.position_m) + ' m on ' + plan.name));
    }
    for (const k of a.evidence || []) box.append(await keyframeFigure(k.keyframe, k.role));
  } catch (e) { box.replaceChildren(); Console.fail(e); }
});

// ---- Furniture graphs -----------------------------------------------------------------------------------------------
// A hypothesis's last match (api/furniture_json.cc MatchJson): which relation it saw between which pieces, in which frame.
const matchText = m => m ? m.located + ' ' + m.relation_seen + ' ' + m.reference + ' (' + m.frame + ' frame, ' + m.score.toFixed(3) + ')' : '';
Console.views.furniture = {
  async show() {
    const graphs = (await Api.get(M() + '/furniture-graphs?limit=100')).furniture_graphs;
    $('#graph-list').replaceChildren(...graphs.map(g => el('li', { 'data-graph': g.id, onclick: () => this.open(g.id) },
      'graph ' + g.id + ' (' + g.descriptions + ' descriptions)')));
    if (graphs.length) await this.open(this.selected || graphs[0].id);
  },
  async open(id) {
    this.selected = id;
    for (const li of document.querySelectorAll('#graph-list li')) li.classList.toggle('selected', Number(li.dataset.graph) === id);
    const g = await Api.get(M() + '/furniture-graphs/' + id);
    const hyp = await Api.get(M() + '/furniture-graphs/' + id + '/hypotheses?limit=5');
    const plan = await floorPlan();
    let canvas, geo;
    if (plan) { canvas = plan.canvas; geo = plan.geo; } else {
      canvas = el('canvas', { width: '400', height: '400' });
      geo = { resolution: 0.02, origin: [-4, -4], height: 400 };
    }
    const scale = 3;  // drawn 3x so that words are legible over the cells
    const big = el('canvas', { width: String(canvas.width * scale), height: String(canvas.height * scale), id: 'graph-canvas' });
    const ctx = big.getContext('2d');
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(canvas, 0, 0, big.width, big.height);
    const px = (x, y) => Images.toPixel(geo, x, y).map(v => v * scale);
    const best = (hyp.hypotheses[0] || {}).labels || {};
    const centre = {};
    for (const v of g.vertices) {
      const [cx, cy] = px(v.position[0], v.position[1]);
      centre[v.id] = [cx, cy];
      const w = v.extent[0] / geo.resolution * scale, h = v.extent[1] / geo.resolution * scale;
      ctx.strokeStyle = '#2563eb'; ctx.lineWidth = 2;
      ctx.strokeRect(cx - w / 2, cy - h / 2, w, h);
      ctx.fillStyle = '#1e3a8a'; ctx.font = '12px sans-serif';
      ctx.fillText(v.id + ': ' + (best[v.id] || topLabel(v.categories)), cx - w / 2, cy - h / 2 - 3);
    }
    ctx.strokeStyle = '#d97706'; ctx.fillStyle = '#92400e';
    for (const e of g.edges) {
      const a = centre[e.a], b = centre[e.b];
      if (!a || !b) continue;
      ctx.beginPath(); ctx.moveTo(a[0], a[1]); ctx.lineTo(b[0], b[1]); ctx.stroke();
      const rel = e.a_relative_to_b && (e.a_relative_to_b.relation || topLabel(e.a_relative_to_b));
      ctx.fillText(rel || '', (a[0] + b[0]) / 2, (a[1] + b[1]) / 2);
    }
    big.style.maxWidth = '720px';
    const describe = el('form', { class: 'inline edit' }, el('input', { name: 'text', size: '40', placeholder: 'the cup is on the table left of the chair' }),
      el('button', {}, 'ground description'));
    describe.addEventListener('submit', async ev => {
      ev.preventDefault();
      try { await Api.post(M() + '/furniture-graphs/' + id + '/descriptions', { text: describe.text.value }); await this.open(id); } catch (x) { Console.fail(x); }
    });
    const ids = g.vertices.map(v => v.id);
    const speak = el('form', { class: 'inline' }, el('select', { name: 'located' }, ...ids.map(v => el('option', {}, v))),
      el('select', { name: 'reference' }, ...ids.slice().reverse().map(v => el('option', {}, v))), el('button', {}, 'describe and speak'));
    const said = el('div', { class: 'sentence' });
    speak.addEventListener('submit', async ev => {
      ev.preventDefault();
      try {
        const u = await Api.post(M() + '/furniture-graphs/' + id + ':describe', { located: speak.located.value, reference: speak.reference.value });
        said.textContent = u.sentence || ('The ' + (u.located.name || u.located.vertex) + ' is ' + u.phrase + ' the ' +
          (u.reference.name || u.reference.vertex) + '.');
        if (window.speechSynthesis) speechSynthesis.speak(new SpeechSynthesisUtterance(said.textContent));
      } catch (x) { Console.fail(x); }
    });
    $('#graph-detail').replaceChildren(el('h3', {}, 'graph ' + id + ': ' + g.vertices.length + ' pieces, ' + g.edges.length + ' edges'),
      Images.figure(big, 'best hypothesis labels; edges with relations'), el('h4', {}, 'n-best hypotheses'),
      el('table', { class: 'table', id: 'hypotheses' }, el('tr', {}, el('th', {}, 'rank'), el('th', {}, 'score'), el('th', {}, 'scheme'),
        el('th', {}, 'last match'), el('th', {}, 'labels')),
        ...hyp.hypotheses.map(h => el('tr', { 'data-rank': String(h.rank) }, el('td', {}, String(h.rank)), el('td', {}, h.score.toFixed(3)),
          el('td', { class: 'scheme' }, h.scheme), el('td', { class: 'last-match' }, matchText(h.last_match)), el('td', {}, JSON.stringify(h.labels))))),
      el('h4', {}, 'descriptions'), el('ol', {}, ...g.groundings.map(d => el('li', {}, d.input ? (d.input.text || (d.input.located + ' ' + d.input.relation + ' ' + d.input.reference)) : JSON.stringify(d)))),
      describe, speak, said);
    Console.applyRole();
  },
};

// ---- Jobs, forgetting, backups ------------------------------------------------------------------------------------------
Console.views.jobs = {
  rows: {},
  async show() {
    const jobs = (await Api.get('/v1/jobs?limit=100')).jobs.filter(j => j.map === null || j.map === Console.map);
    this.rows = {};
    $('#job-table tbody').replaceChildren(...jobs.map(j => this.row(j)));
  },
  row(j) {
    const tr = el('tr', { 'data-job': j.id }, el('td', {}, String(j.id)), el('td', {}, j.kind), el('td', {}, j.status), el('td', {}, j.stage),
      el('td', {}, el('progress', { max: '1', value: String(j.progress) }), ' ' + Math.round(j.progress * 100) + '%'),
      el('td', {}, j.error ? 'error: ' + j.error : j.result ? JSON.stringify(j.result).slice(0, 160) : ''));
    this.rows[j.id] = tr;
    return tr;
  },
  onMessage(kind, job) {
    if (kind !== 'job') return;
    const old = this.rows[job.id];
    const tr = this.row(job);
    if (old) old.replaceWith(tr); else $('#job-table tbody').prepend(tr);
  },
  async wait(ticket) {
    for (;;) {
      const j = await Api.get('/v1/jobs/' + ticket.job);
      this.onMessage('job', j);
      if (j.status === 'succeeded' || j.status === 'failed') return j;
      await new Promise(r => setTimeout(r, 300));
    }
  },
  policy() {
    const f = $('#forget-form');
    const p = { superseded_models: f.superseded_models.checked };
    if (f.keyframe_max_age_s.value) p.keyframe_max_age_s = Number(f.keyframe_max_age_s.value);
    if (f.event_max_age_s.value) p.event_max_age_s = Number(f.event_max_age_s.value);
    return p;
  },
};
$('#forget-form').addEventListener('submit', async ev => {
  ev.preventDefault();
  const v = Console.views.jobs, box = $('#forget-report');
  try {
    const policy = v.policy();
    const dry = await v.wait(await Api.post(M() + ':forget', { policy, dry_run: true }));
    const real = el('button', { id: 'forget-real', class: 'edit admin-only' }, 'forget for real');
    real.addEventListener('click', async () => {
      if (!confirm('Delete what the dry run counted?')) return;
      try {
        const done = await v.wait(await Api.post(M() + ':forget', { policy, dry_run: false }));
        box.replaceChildren(el('h4', {}, 'forgotten (job ' + done.id + ')'), kv(done.result || { error: done.error }));
      } catch (x) { Console.fail(x); }
    });
    box.replaceChildren(el('h4', {}, 'dry run (job ' + dry.id + '): what would go'), kv(dry.result || { error: dry.error }), real);
  } catch (e) { Console.fail(e); }
});
$('#backup-form').addEventListener('submit', async ev => {
  ev.preventDefault();
  try {
    const label = ev.target.label.value.trim();
    const j = await Console.views.jobs.wait(await Api.post('/v1/backups', label ? { label } : {}));
    Console.status('backup job ' + j.id + ' ' + j.status);
  } catch (e) { Console.fail(e); }
});
