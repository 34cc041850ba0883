// Frame comparison shared by the engine pages (phaser-harness.js,
// sprites-harness.js): two readPixels frames of a scene's viewport,
// pixel for pixel. Pixels whose centre lies exactly on a texel edge of an
// element (within float32 position rounding) are the only ones allowed to
// differ (as harness.js and render::count_off_texel_edges): there the last
// bits of the interpolated u, v pick the texel on either side, in any
// renderer.
const TEXEL_EDGE_TOLERANCE = 1 / 65536; // render::kTexelEdgeTolerance

function onTexelEdge(t, tol = TEXEL_EDGE_TOLERANCE) {
  return Math.abs(t - Math.round(t)) <= tol;
}

// One float32 step at |x| (as harness.js): the engine and the layer hand
// the GPU float32 screen positions rounded differently (the engine's quad
// corners, the layer's polygon vertices), so u, v at a pixel centre may
// differ by about that much over the element's scale; examples/meadow.json's
// pixel (542, 69) lies 3.0e-5 texels from a "moons" texel edge, under that.
function ulp32(x) {
  const e = Math.floor(Math.log2(Math.max(Math.abs(x), 2 ** -126)));
  return 2 ** (e - 23);
}

/**
 * `elements`: [{rect: [x, y, w, h], transform: [a, b, c, d, tx, ty]}] in
 * world pixels; `viewport`: {x, y} of the frames' top-left; `a`, `b`:
 * bottom-up RGBA rows (readPixels) of `width` x `height`.
 */
export function compareFrames(elements, viewport, a, b, width, height) {
  const maps = elements.map(({ rect, transform }) => {
    const [ma, mb, mc, md, tx, ty] = transform ?? [1, 0, 0, 1, 0, 0];
    return { rect, a: ma, b: mb, c: mc, d: md, tx, ty, det: ma * md - mb * mc };
  });
  let differ = 0, offEdges = 0;
  const examples = [];
  const tol = TEXEL_EDGE_TOLERANCE;
  for (let row = 0; row < height; ++row)
    for (let x = 0; x < width; ++x) {
      const i = ((height - 1 - row) * width + x) * 4;
      if (a[i] === b[i] && a[i + 1] === b[i + 1] && a[i + 2] === b[i + 2] && a[i + 3] === b[i + 3]) continue;
      ++differ;
      const sx = viewport.x + x + 0.5, sy = viewport.y + row + 0.5;
      let explained = false;
      for (const m of maps) {
        const px = sx - m.tx, py = sy - m.ty;
        const u = m.rect[0] + (m.d * px - m.c * py) / m.det, v = m.rect[1] + (-m.b * px + m.a * py) / m.det;
        if (u < m.rect[0] - tol || v < m.rect[1] - tol || u > m.rect[0] + m.rect[2] + tol || v > m.rect[1] + m.rect[3] + tol) continue;
        const edge = Math.max(tol, ulp32(Math.max(Math.abs(sx), Math.abs(sy))) / Math.sqrt(Math.abs(m.det)));
        if (onTexelEdge(u, edge) || onTexelEdge(v, edge)) {
          explained = true;
          break;
        }
      }
      if (!explained) {
        ++offEdges;
        if (examples.length < 5) examples.push(`(${x},${row}) first ${[...a.subarray(i, i + 4)]} second ${[...b.subarray(i, i + 4)]}`);
      }
    }
  return { differ, offEdges, examples };
}

export function readPixels(gl) {
  const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
  const px = new Uint8Array(w * h * 4);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
  return px;
}

export function rendererString(gl) {
  const ext = gl.getExtension('WEBGL_debug_renderer_info');
  return gl.getParameter(ext ? ext.UNMASKED_RENDERER_WEBGL : gl.RENDERER);
}
