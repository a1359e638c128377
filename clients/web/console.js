// The console's frame: the map selector, the token and its role (edit controls shown only to roles that may use
// them), the tabs, the status line and the live stream that keeps the open view current.
'use strict';

const $ = (sel, root) => (root || document).querySelector(sel);
const el = (tag, attrs, ...children) => {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) {
    if (k === 'onclick') e.addEventListener('click', v);
    else if (k === 'class') e.className = v;
    else if (k === 'style') e.style.cssText = v;  // through the CSSOM: the page's CSP allows no inline style attribute
    else e.setAttribute(k, v);
  }
  for (const c of children) if (c !== null && c !== undefined) e.append(c);
  return e;
};
const fmtTime = ns => (ns === null || ns === undefined) ? '' : new Date(Number(BigInt(ns) / 1000000n)).toISOString().replace('T', ' ').slice(0, 19);
const fmtVec = v => v ? v.map(x => x.toFixed(2)).join(', ') : '';
const topLabel = labels => {
  let best = '', w = -1;
  for (const [k, v] of Object.entries(labels || {})) if (v > w) { best = k; w = v; }
  return best;
};

const Console = {
  map: null,
  role: null,          // public | reader | writer | admin
  view: 'layers',
  views: {},           // name -> {show(), onMessage(kind, data)}
  stopStream: null,
  roleRank: { public: 0, reader: 1, writer: 2, admin: 3 },
  may(role) { return (Console.roleRank[Console.role] || 0) >= Console.roleRank[role]; },
  status(text, isError) {
    const s = $('#status');
    s.textContent = text || '';
    s.style.color = isError ? '#b91c1c' : '#065f46';
  },
  fail(e) { Console.status((e.code ? e.code + ': ' : '') + e.message + (e.field ? ' (' + e.field + ')' : ''), true); },
  // Edit controls: elements with class edit (writer) or admin-only (admin) are removed from view for other roles.
  applyRole() {
    for (const e of document.querySelectorAll('.edit')) e.hidden = !Console.may(e.classList.contains('admin-only') ? 'admin' : 'writer');
    for (const e of document.querySelectorAll('.admin-only')) e.hidden = !Console.may('admin');
    $('#role').textContent = 'role ' + (Console.role || '?');
  },
  async whoami() {
    try {
      const w = await Api.get('/v1/whoami');
      Console.role = w.role || 'public';
    } catch (e) {
      Console.role = 'public';
      Console.fail(e);
    }
    Console.applyRole();
  },
  async loadMaps() {
    const sel = $('#map');
    try {
      const maps = (await Api.get('/v1/maps?limit=1000')).maps;
      sel.replaceChildren(...maps.map(m => el('option', { value: m.id }, m.id + (m.name && m.name !== m.id ? ' (' + m.name + ')' : ''))));
      const wanted = new URLSearchParams(location.hash.slice(1)).get('map');
      if (wanted && maps.some(m => m.id === wanted)) sel.value = wanted;
      Console.map = sel.value || null;
    } catch (e) { Console.fail(e); }
  },
  show(view) {
    Console.view = view;
    for (const b of document.querySelectorAll('#tabs button')) b.classList.toggle('active', b.dataset.view === view);
    for (const s of document.querySelectorAll('.view')) s.classList.toggle('active', s.id === 'view-' + view);
    const params = new URLSearchParams(location.hash.slice(1));
    params.set('view', view);
    if (Console.map) params.set('map', Console.map);
    history.replaceState(null, '', '#' + params.toString());
    if (Console.map && Console.views[view]) {
      Console.status('');
      Console.views[view].show().then(() => Console.applyRole()).catch(Console.fail);
    }
  },
  startStream() {
    if (Console.stopStream) Console.stopStream();
    if (!Console.map) return;
    Console.stopStream = Api.stream(Console.map, (kind, data) => {
      for (const v of Object.values(Console.views)) if (v.onMessage) v.onMessage(kind, data);
    }, on => { $('#live').textContent = on ? 'stream live' : 'stream off'; $('#live').classList.toggle('on', on); });
  },
  async start() {
    const saved = sessionStorage.getItem('anchordb-token');
    if (saved) $('#token').value = saved;
    $('#token').addEventListener('change', async () => {
      sessionStorage.setItem('anchordb-token', $('#token').value.trim());
      await Console.whoami();
      await Console.loadMaps();
      Console.startStream();
      Console.show(Console.view);
    });
    $('#map').addEventListener('change', () => { Console.map = $('#map').value; Console.startStream(); Console.show(Console.view); });
    for (const b of document.querySelectorAll('#tabs button')) b.addEventListener('click', () => Console.show(b.dataset.view));
    await Console.whoami();
    await Console.loadMaps();
    Console.startStream();
    const view = new URLSearchParams(location.hash.slice(1)).get('view');
    Console.show(view && $('#view-' + view) ? view : 'layers');
  },
};

window.addEventListener('DOMContentLoaded', () => Console.start());
