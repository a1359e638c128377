// The API as the console uses it: JSON calls with the token field's Bearer token, errors as ApiError carrying the
// server's {code, message, field}, images as decoded bitmaps, and the live stream (events:stream) read with fetch so
// that it can carry the token and Last-Event-ID itself.
'use strict';

class ApiError extends Error {
  constructor(status, error) {
    super(error.message || ('HTTP ' + status));
    this.status = status;
    this.code = error.code || 'http_' + status;
    this.field = error.field || null;
  }
}

const Api = {
  token() { return document.getElementById('token').value.trim(); },
  headers(extra) {
    const h = Object.assign({}, extra || {});
    if (Api.token()) h.Authorization = 'Bearer ' + Api.token();
    return h;
  },
  async call(method, path, body) {
    const init = { method, headers: Api.headers(body !== undefined ? { 'Content-Type': 'application/json' } : {}) };
    if (body !== undefined) init.body = JSON.stringify(body);
    const r = await fetch(path, init);
    const text = await r.text();
    let doc = null;
    try { doc = text ? JSON.parse(text) : null; } catch (e) { doc = null; }
    if (!r.ok) throw new ApiError(r.status, (doc && doc.error) || {});
    return doc;
  },
  get(path) { return Api.call('GET', path); },
  post(path, body) { return Api.call('POST', path, body === undefined ? {} : body); },
  del(path) { return Api.call('DELETE', path); },
  // An image route decoded to an ImageBitmap (pixels exactly as served: no colour conversion).
  async bitmap(path) {
    const r = await fetch(path, { headers: Api.headers() });
    if (!r.ok) {
      let e = {};
      try { e = (await r.json()).error || {}; } catch (x) { /* not JSON */ }
      throw new ApiError(r.status, e);
    }
    return createImageBitmap(await r.blob(), { colorSpaceConversion: 'none', premultiplyAlpha: 'none' });
  },
  // Follows GET /v1/maps/{map}/events:stream: onMessage(kind, data, id) for each message; reconnects with the last id
  // after each response ends (the server ends them on purpose) or fails. Returns a function that stops it.
  stream(map, onMessage, onState) {
    let stopped = false, lastId = null, controller = null;
    const run = async () => {
      while (!stopped) {
        let retryMs = 1000;
        try {
          controller = new AbortController();
          const h = Api.headers();
          if (lastId !== null) h['Last-Event-ID'] = lastId;
          const r = await fetch('/v1/maps/' + encodeURIComponent(map) + '/events:stream', { headers: h, signal: controller.signal });
          if (!r.ok) throw new ApiError(r.status, {});
          onState(true);
          const reader = r.body.getReader();
          const decoder = new TextDecoder();
          let buffer = '';
          for (;;) {
            const { value, done } = await reader.read();
            if (done) break;
            buffer += decoder.decode(value, { stream: true });
            let end;
            while ((end = buffer.indexOf('\n\n')) >= 0) {
              const block = buffer.slice(0, end);
              buffer = buffer.slice(end + 2);
              let id = null, kind = 'message', data = '';
              for (const line of block.split('\n')) {
                if (!line || line[0] === ':') continue;
                const c = line.indexOf(':');
                const field = c < 0 ? line : line.slice(0, c);
                const v = c < 0 ? '' : line.slice(c + 1).replace(/^ /, '');
                if (field === 'id') id = v;
                else if (field === 'event') kind = v;
                else if (field === 'data') data += v;
                else if (field === 'retry') retryMs = parseInt(v, 10) || retryMs;
              }
              if (id !== null) lastId = id;
              if (data) onMessage(kind, JSON.parse(data), id);
            }
          }
        } catch (e) {
          if (stopped) return;
          onState(false);
          retryMs = 2000;
        }
        await new Promise(res => setTimeout(res, retryMs));
      }
    };
    run();
    return () => { stopped = true; if (controller) controller.abort(); onState(false); };
  },
};
