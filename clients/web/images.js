// Pictures of the memory: bitmaps drawn to canvases, the probability colour map and its legend, depth stretched to
// grey, and map-frame geometry (regions, instances, furniture) drawn over a layer image.
'use strict';

const Images = {
  // A small perceptual colour map (dark blue -> green -> yellow), p in [0, 1].
  colour(p) {
    const stops = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];
    const x = Math.min(1, Math.max(0, p)) * (stops.length - 1);
    const i = Math.min(stops.length - 2, Math.floor(x)), t = x - i;
    return stops[i].map((a, k) => Math.round(a + (stops[i + 1][k] - a) * t));
  },
  canvasOf(bitmap, scale) {
    const c = document.createElement('canvas');
    c.width = bitmap.width;
    c.height = bitmap.height;
    c.getContext('2d').drawImage(bitmap, 0, 0);
    if (scale) c.style.width = Math.round(bitmap.width * scale) + 'px';
    return c;
  },
  pixels(canvas) { return canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height); },
  // Probability layers come as grey = (1 - p) * 255 (row 0 = the largest y); shown through the colour map.
  probabilityCanvas(bitmap) {
    const c = Images.canvasOf(bitmap);
    const img = Images.pixels(c);
    for (let i = 0; i < img.data.length; i += 4) {
      const [r, g, b] = Images.colour(1 - img.data[i] / 255);
      img.data[i] = r; img.data[i + 1] = g; img.data[i + 2] = b; img.data[i + 3] = 255;
    }
    c.getContext('2d').putImageData(img, 0, 0);
    return c;
  },
  legend(label) {
    const div = document.createElement('div');
    div.className = 'legend';
    const c = document.createElement('canvas');
    c.width = 100; c.height = 1;
    const ctx = c.getContext('2d');
    for (let x = 0; x < 100; ++x) { const [r, g, b] = Images.colour(x / 99); ctx.fillStyle = `rgb(${r},${g},${b})`; ctx.fillRect(x, 0, 1, 1); }
    div.append(label + ' 0', c, '1');
    return div;
  },
  // Depth PNGs (16-bit millimetres, decoded by the browser to their high byte) stretched over their measured range.
  depthCanvas(bitmap) {
    const c = Images.canvasOf(bitmap);
    const img = Images.pixels(c);
    let lo = 255, hi = 0;
    for (let i = 0; i < img.data.length; i += 4) if (img.data[i] > 0) { lo = Math.min(lo, img.data[i]); hi = Math.max(hi, img.data[i]); }
    const span = Math.max(1, hi - lo);
    for (let i = 0; i < img.data.length; i += 4) {
      const v = img.data[i];
      const g = v === 0 ? 0 : 40 + Math.round(215 * (hi - v) / span);  // near = bright, no depth = black
      img.data[i] = img.data[i + 1] = img.data[i + 2] = g; img.data[i + 3] = 255;
    }
    c.getContext('2d').putImageData(img, 0, 0);
    return c;
  },
  // Non-zero pixels of a mask image (movable / dynamic layers are 0 / 255 masks).
  countSet(canvas) {
    const d = Images.pixels(canvas).data;
    let n = 0;
    for (let i = 0; i < d.length; i += 4) if (d[i] > 0) ++n;
    return n;
  },
  // Map frame [m] -> pixel of a layer image (REP-103 x right, y up; image row 0 at the top: the largest y).
  toPixel(geo, x, y) {
    return [(x - geo.origin[0]) / geo.resolution, geo.height - (y - geo.origin[1]) / geo.resolution];
  },
  figure(canvas, caption) {
    const f = document.createElement('figure');
    f.append(canvas);
    if (caption !== undefined) {
      const c = document.createElement('figcaption');
      if (caption instanceof Node) c.append(caption); else c.textContent = caption;
      f.append(c);
    }
    return f;
  },
};
