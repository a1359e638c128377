// The scene models view: static / movable / dynamic / reliability side by side, the merge report (per earlier model
// its ICP correction and the pixels each rule took or rejected) and the keyframe strip.
'use strict';

// The rules of the merge (services/scene/scene_documents.cc "pixels"), in the order the merge applies them.
const MERGE_RULES = ['rasterised', 'supported', 'replaced_farther', 'rear_projected', 'filled_unknown', 'rejected_fov',
                     'rejected_occlusion', 'rejected_neighbourhood', 'rejected_uncertain'];

function mergeReport(m) {
  const used = m.models_used || [];
  const rules = MERGE_RULES.filter(r => used.some(u => u.pixels && u.pixels[r] !== undefined));
  const rows = used.map(u => {
    const icp = u.icp || {}, c = icp.correction || {};
    return el('tr', { 'data-scene': u.scene }, el('td', {}, String(u.scene)),
      el('td', {}, (icp.applied ? fmtVec(c.translation_m || []) + ' m, ' + ((c.rotation_rad || 0) * 180 / Math.PI).toFixed(2) + ' deg'
        : 'not applied') + (icp.verdict ? ' (' + icp.verdict + ')' : '')),
      ...rules.map(r => el('td', { 'data-rule': r }, String((u.pixels || {})[r] ?? ''))));
  });
  const rest = {};
  for (const k of ['requested', 'strategy', 'performed', 'superseded', 'pose_corrected_by_scene']) if (m[k] !== undefined) rest[k] = m[k];
  if (m.candidates) rest.candidates = m.candidates.map(c => c.scene + ' (overlap ' + Number(c.overlap).toFixed(2) + ')').join(', ');
  if (m.timing_ms) rest.timing_ms = Object.entries(m.timing_ms).map(([k, v]) => k + ' ' + Number(v).toFixed(1)).join(', ');
  return el('div', {}, el('table', { class: 'table', id: 'merge-models' }, el('tr', {}, el('th', {}, 'model'),
    el('th', {}, 'ICP correction'), ...rules.map(r => el('th', {}, r.replace(/_/g, ' ')))), ...rows),
    el('p', { class: 'note' }, 'pixels per rule of the merge, per earlier model used'), kv(rest));
}

// The reliability layer (8-bit weight, clamped at 255) through the colour map, scaled to its largest weight.
function reliabilityCanvas(bitmap, summary) {
  const c = Images.canvasOf(bitmap);
  const img = Images.pixels(c);
  let max = 0;
  for (let i = 0; i < img.data.length; i += 4) max = Math.max(max, img.data[i]);
  for (let i = 0; i < img.data.length; i += 4) {
    const [r, g, b] = Images.colour(max ? img.data[i] / max : 0);
    img.data[i] = r; img.data[i + 1] = g; img.data[i + 2] = b; img.data[i + 3] = 255;
  }
  c.getContext('2d').putImageData(img, 0, 0);
  c.dataset.maxValue = max;
  c.dataset.maxWeight = summary.max_weight;
  return c;
}

Console.views.scenes = {
  async show() {
    const scenes = (await Api.get(M() + '/scenes?limit=100')).scenes;
    const list = $('#scene-list');
    list.replaceChildren(...scenes.map(s => el('li', { 'data-scene': s.id, onclick: () => this.open(s.id) },
      'scene ' + s.id + ' ' + s.status + ' (' + s.persisted_frames + ' frames)')));
    if (scenes.length) await this.open(this.selected && scenes.some(s => s.id === this.selected) ? this.selected : scenes[0].id);
  },
  async open(id) {
    this.selected = id;
    for (const li of document.querySelectorAll('#scene-list li')) li.classList.toggle('selected', Number(li.dataset.scene) === id);
    const s = await Api.get(M() + '/scenes/' + id);
    const detail = $('#scene-detail');
    const row = el('div', { class: 'grid' });
    for (const layer of ['static', 'movable', 'dynamic', 'reliability']) {
      const path = M() + '/scenes/' + id + '/layers/' + layer;
      const bitmap = await Api.bitmap(path + '?format=png');
      let canvas, caption = layer;
      if (layer === 'static') {
        canvas = Images.depthCanvas(bitmap);
      } else if (layer === 'reliability') {
        const summary = await Api.get(path + '?format=json');
        canvas = reliabilityCanvas(bitmap, summary);
        caption = el('div', {}, 'reliability: max weight ' + Number(summary.max_weight).toFixed(1) + ', mean ' +
          Number(summary.mean_weight).toFixed(2), Images.legend('weight / max'));
      } else {
        canvas = Images.canvasOf(bitmap);
        canvas.dataset.setPixels = Images.countSet(canvas);
        caption = layer + ' (' + canvas.dataset.setPixels + ' pixels set)';
      }
      canvas.dataset.layer = layer;
      canvas.style.width = '240px';
      row.append(Images.figure(canvas, caption));
    }
    const strip = el('div', { class: 'strip', id: 'keyframe-strip' });
    for (const k of s.keyframes || []) {
      const b = await Api.bitmap(M() + '/keyframes/' + k.id + '/depth');
      const c = Images.depthCanvas(b);
      strip.append(Images.figure(c, k.kind + ' ' + k.id + ' ' + fmtTime(k.stamp_ns)));
    }
    detail.replaceChildren(el('h3', {}, 'scene ' + id + ' (' + s.status + ')'),
      kv({ frames: s.frames, movable_pixels: s.statistics.movable_pixels, dynamic_pixels: s.statistics.dynamic_pixels,
           known_background_pixels: s.statistics.known_background_pixels, started: fmtTime(s.started_ns), superseded_by: s.superseded_by }),
      row, el('h4', {}, 'merge report'), s.merge ? mergeReport(s.merge) : 'no merge', el('h4', {}, 'keyframes'), strip);
    detail.dataset.movablePixels = s.statistics.movable_pixels;
  },
};
