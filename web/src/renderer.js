// A WebGL 2 renderer for depthcull's meshes (docs/engine-integration.md):
// clear depth to 0, the opaque pass in file order (front to back) with depth
// test GREATER and depth writes, then the blend pass in file order (back to
// front) with depth writes off and the documented blend factors.
//
// It shares a context with an engine: draw() saves every GL state it
// changes and puts it back before returning (the list is STATE below), and
// the depth buffer is the one thing it leaves changed (cleared, then
// written by the opaque pass). It draws into whatever framebuffer, viewport,
// scissor, stencil test and colour mask the caller has set.
import { DepthcullError } from './index.js';

const VERTEX_FLOATS = 9;
const BLEND_NAMES = ['alpha', 'add', 'multiply', 'opaque'];

const VERTEX = `#version 300 es
precision highp float;
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec2 a_uv;
layout(location = 2) in vec4 a_color;
uniform mat3 u_matrix; // world pixels to clip space
uniform bool u_premultiply_color;
out vec2 v_uv;
out vec4 v_color;
void main() {
  vec3 p = u_matrix * vec3(a_position.xy, 1.0);
  gl_Position = vec4(p.xy, a_position.z * 2.0 - 1.0, 1.0);
  v_uv = a_uv;
  // With premultiplied textures the colour is premultiplied too, as
  // PixiJS's batcher does (vColor = (rgb * a, a)).
  v_color = u_premultiply_color ? vec4(a_color.rgb * a_color.a, a_color.a) : a_color;
}`;

// No discard: it would switch off early depth rejection, the point of the
// opaque pass. u_mode: 0 as is, 1 premultiply (multiply on straight-alpha
// textures), 2 alpha forced to 1 (opaque).
const FRAGMENT = (precision) => `#version 300 es
precision ${precision} float;
uniform sampler2D u_texture;
uniform int u_mode;
in vec2 v_uv;
in vec4 v_color;
out vec4 o_color;
void main() {
  vec4 c = texture(u_texture, v_uv) * v_color;
  if (u_mode == 1) c.rgb *= c.a;
  else if (u_mode == 2) c.a = 1.0;
  o_color = c;
}`;

// The states draw() changes, each saved before and restored after.
const STATE = [
  'CURRENT_PROGRAM', 'VERTEX_ARRAY_BINDING', 'ARRAY_BUFFER_BINDING', 'ACTIVE_TEXTURE',
  'BLEND', 'BLEND_SRC_RGB', 'BLEND_DST_RGB', 'BLEND_SRC_ALPHA', 'BLEND_DST_ALPHA',
  'BLEND_EQUATION_RGB', 'BLEND_EQUATION_ALPHA', 'DEPTH_TEST', 'DEPTH_FUNC', 'DEPTH_WRITEMASK',
  'DEPTH_CLEAR_VALUE', 'CULL_FACE',
];

// The attributes of the bound VAO over the bound ARRAY_BUFFER: 9 floats a
// vertex, or with colour bytes (setMeshes' and draw's colorByte) 5 floats
// and 4 normalized bytes (24 bytes).
function setVertexLayout(gl, colorBytes) {
  const stride = colorBytes ? 24 : VERTEX_FLOATS * 4;
  gl.enableVertexAttribArray(0);
  gl.vertexAttribPointer(0, 3, gl.FLOAT, false, stride, 0);
  gl.enableVertexAttribArray(1);
  gl.vertexAttribPointer(1, 2, gl.FLOAT, false, stride, 12);
  gl.enableVertexAttribArray(2);
  if (colorBytes) gl.vertexAttribPointer(2, 4, gl.UNSIGNED_BYTE, true, stride, 20);
  else gl.vertexAttribPointer(2, 4, gl.FLOAT, false, stride, 20);
}

// `src`'s 9-float vertices into the 24-byte layout from vertex `at` of
// f32/u8 (views of one buffer): position and uv as floats, the colour as
// colorByte's bytes.
function packVertices(src, f32, u8, at, colorByte) {
  const n = src.length / VERTEX_FLOATS;
  for (let k = 0; k < n; ++k) {
    const s = k * VERTEX_FLOATS, d = (at + k) * 6;
    for (let c = 0; c < 5; ++c) f32[d + c] = src[s + c];
    for (let c = 0; c < 4; ++c) u8[(d + 5) * 4 + c] = colorByte(src[s + 5 + c], c);
  }
}

function compile(gl, type, source) {
  const shader = gl.createShader(type);
  gl.shaderSource(shader, source);
  gl.compileShader(shader);
  if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS) && !gl.isContextLost())
    throw new DepthcullError(`MeshRenderer: shader does not compile: ${gl.getShaderInfoLog(shader).split('\n')[0]}`);
  return shader;
}

/** Column-major mat3 mapping world pixels of `camera` {x, y, width, height} to clip space, y down (as a canvas shows it). */
export function cameraMatrix({ x = 0, y = 0, width, height, flipY = true }) {
  const sx = 2 / width, sy = (flipY ? -2 : 2) / height;
  return new Float32Array([sx, 0, 0, 0, sy, 0, -x * sx - 1, -y * sy + (flipY ? 1 : -1), 1]);
}

export class MeshRenderer {
  /**
   * `gl`: a WebGL2RenderingContext whose framebuffer has a depth buffer.
   * `premultipliedAlpha`: textures hold premultiplied colours (PixiJS
   * uploads them so); the vertex colour is then premultiplied and the blend
   * factors are PixiJS's (normal ONE, ONE_MINUS_SRC_ALPHA; add ONE, ONE;
   * multiply DST_COLOR, ONE_MINUS_SRC_ALPHA / ONE, ONE_MINUS_SRC_ALPHA).
   * Otherwise straight alpha with docs/engine-integration.md's factors.
   * `fragmentPrecision`: 'highp', or 'mediump' as PixiJS's shaders ask for
   * (llvmpipe computes mediump in 16 bits: texture * colour then rounds as
   * Pixi's does).
   */
  constructor(gl, { premultipliedAlpha = false, fragmentPrecision = 'highp' } = {}) {
    if (fragmentPrecision !== 'highp' && fragmentPrecision !== 'mediump') throw new DepthcullError(`MeshRenderer: fragmentPrecision "${fragmentPrecision}" (expected highp or mediump)`);
    if (typeof WebGL2RenderingContext === 'undefined' || !(gl instanceof WebGL2RenderingContext))
      throw new DepthcullError('MeshRenderer: needs a WebGL 2 context');
    this.gl = gl;
    this.premultipliedAlpha = premultipliedAlpha;
    this.stats = { draws: 0, triangles: 0 };
    const saved = this.#save();
    try {
      const program = gl.createProgram();
      gl.attachShader(program, compile(gl, gl.VERTEX_SHADER, VERTEX));
      gl.attachShader(program, compile(gl, gl.FRAGMENT_SHADER, FRAGMENT(fragmentPrecision)));
      gl.linkProgram(program);
      if (!gl.getProgramParameter(program, gl.LINK_STATUS) && !gl.isContextLost())
        throw new DepthcullError(`MeshRenderer: shaders do not link: ${gl.getProgramInfoLog(program).split('\n')[0]}`);
      this.program = program;
      this.uMatrix = gl.getUniformLocation(program, 'u_matrix');
      this.uMode = gl.getUniformLocation(program, 'u_mode');
      this.uPremultiply = gl.getUniformLocation(program, 'u_premultiply_color');
      this.uTexture = gl.getUniformLocation(program, 'u_texture');
      this.vao = gl.createVertexArray();
      this.vbo = gl.createBuffer();
      this.ibo = gl.createBuffer();
    } finally {
      this.#restore(saved);
    }
    this.draws = [];
    this.textures = [];
  }

  #save() {
    const gl = this.gl;
    const s = {};
    for (const name of STATE) s[name] = gl.getParameter(gl[name]);
    // Unit 0 is the one we bind on: its texture and sampler object.
    gl.activeTexture(gl.TEXTURE0);
    s.TEXTURE_BINDING_2D = gl.getParameter(gl.TEXTURE_BINDING_2D);
    s.SAMPLER_BINDING = gl.getParameter(gl.SAMPLER_BINDING);
    return s;
  }

  #restore(s) {
    const gl = this.gl;
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, s.TEXTURE_BINDING_2D);
    gl.bindSampler(0, s.SAMPLER_BINDING);
    gl.activeTexture(s.ACTIVE_TEXTURE);
    gl.useProgram(s.CURRENT_PROGRAM);
    gl.bindVertexArray(s.VERTEX_ARRAY_BINDING);
    gl.bindBuffer(gl.ARRAY_BUFFER, s.ARRAY_BUFFER_BINDING);
    s.BLEND ? gl.enable(gl.BLEND) : gl.disable(gl.BLEND);
    gl.blendFuncSeparate(s.BLEND_SRC_RGB, s.BLEND_DST_RGB, s.BLEND_SRC_ALPHA, s.BLEND_DST_ALPHA);
    gl.blendEquationSeparate(s.BLEND_EQUATION_RGB, s.BLEND_EQUATION_ALPHA);
    s.DEPTH_TEST ? gl.enable(gl.DEPTH_TEST) : gl.disable(gl.DEPTH_TEST);
    gl.depthFunc(s.DEPTH_FUNC);
    gl.depthMask(s.DEPTH_WRITEMASK);
    gl.clearDepth(s.DEPTH_CLEAR_VALUE);
    s.CULL_FACE ? gl.enable(gl.CULL_FACE) : gl.disable(gl.CULL_FACE);
  }

  /**
   * The meshes (parseMeshes's result) into one vertex and one index buffer:
   * WebGL 2 has no base vertex, so each draw's indices are offset by its
   * first vertex. `colorByte(c, channel)`: the colours as normalized bytes (0..255)
   * instead of floats, as PixiJS's batcher feeds its shader (the GPU's byte
   * to float conversion is not always the correctly rounded c / 255).
   */
  setMeshes(meshes, { colorByte } = {}) {
    const gl = this.gl;
    let vertexCount = 0, indexCount = 0;
    for (const d of meshes.draws) {
      vertexCount += d.vertices.length / VERTEX_FLOATS;
      indexCount += d.indices.length;
    }
    const stride = colorByte ? 24 : VERTEX_FLOATS * 4;
    const bytes = new ArrayBuffer(vertexCount * stride);
    const f32 = new Float32Array(bytes), u8 = new Uint8Array(bytes);
    const indices = new Uint32Array(indexCount);
    this.draws = [];
    let v = 0, i = 0;
    for (const d of meshes.draws) {
      const n = d.vertices.length / VERTEX_FLOATS;
      if (!colorByte) f32.set(d.vertices, v * VERTEX_FLOATS);
      else packVertices(d.vertices, f32, u8, v, colorByte);
      for (let k = 0; k < d.indices.length; ++k) indices[i + k] = d.indices[k] + v;
      this.draws.push({ image: d.image, pass: d.pass, blend: d.blend, first: i, count: d.indices.length });
      v += n;
      i += d.indices.length;
    }
    this.depthTest = meshes.depthTest;
    this.meshes = meshes;
    const saved = this.#save();
    try {
      gl.bindVertexArray(this.vao);
      gl.bindBuffer(gl.ARRAY_BUFFER, this.vbo);
      gl.bufferData(gl.ARRAY_BUFFER, u8, gl.STATIC_DRAW);
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.ibo); // VAO state
      gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, indices, gl.STATIC_DRAW);
      setVertexLayout(gl, !!colorByte);
    } finally {
      this.#restore(saved);
    }
  }

  /** One WebGLTexture per image of the meshes (index as `meshes.images`), made by the caller (or uploadImages). */
  setTextures(textures) {
    this.textures = textures;
  }

  /**
   * Makes a texture per image from decoded sources (ImageBitmap, HTMLImageElement,
   * ImageData, canvas; null for a `fill` image), sampled with the meshes'
   * filter, clamped. Straight alpha unless `premultipliedAlpha`.
   * `fillsOnly`: only the `fill` images (null for the others).
   */
  uploadImages(sources, { fillsOnly = false } = {}) {
    const gl = this.gl;
    const meshes = this.meshes;
    if (!meshes) throw new DepthcullError('MeshRenderer: uploadImages before setMeshes');
    const unpack = ['UNPACK_FLIP_Y_WEBGL', 'UNPACK_PREMULTIPLY_ALPHA_WEBGL', 'UNPACK_ALIGNMENT', 'UNPACK_COLORSPACE_CONVERSION_WEBGL', 'PIXEL_UNPACK_BUFFER_BINDING'];
    const savedUnpack = unpack.map((n) => gl.getParameter(gl[n]));
    const saved = this.#save();
    const textures = [];
    try {
      gl.bindBuffer(gl.PIXEL_UNPACK_BUFFER, null);
      gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, false);
      gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, this.premultipliedAlpha);
      gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
      gl.pixelStorei(gl.UNPACK_COLORSPACE_CONVERSION_WEBGL, gl.NONE);
      const filter = meshes.filter === 'linear' ? gl.LINEAR : gl.NEAREST;
      meshes.images.forEach((img, i) => {
        if (fillsOnly && !img.fill) return textures.push(null);
        const t = gl.createTexture();
        gl.bindTexture(gl.TEXTURE_2D, t);
        gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, filter);
        gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, filter);
        gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
        gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
        if (img.fill) {
          const c = [0, 2, 4].map((k) => parseInt(img.fill.slice(k, k + 2), 16));
          const px = new Uint8Array(16 * 16 * 4);
          for (let p = 0; p < 256; ++p) px.set([...c, 255], p * 4);
          gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA8, 16, 16, 0, gl.RGBA, gl.UNSIGNED_BYTE, px);
        } else {
          const src = sources[i];
          if (!src) throw new DepthcullError(`MeshRenderer: no image for "${img.id}" (${img.path})`);
          gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA8, gl.RGBA, gl.UNSIGNED_BYTE, src);
        }
        textures.push(t);
      });
    } finally {
      this.#restore(saved);
      unpack.forEach((n, k) => (n === 'PIXEL_UNPACK_BUFFER_BINDING' ? gl.bindBuffer(gl.PIXEL_UNPACK_BUFFER, savedUnpack[k]) : gl.pixelStorei(gl[n], savedUnpack[k])));
    }
    this.textures = textures;
    return textures;
  }

  #blend(blend) {
    const gl = this.gl;
    if (blend === 'opaque') {
      gl.disable(gl.BLEND);
      return 2;
    }
    gl.enable(gl.BLEND);
    gl.blendEquation(gl.FUNC_ADD);
    if (this.premultipliedAlpha) {
      if (blend === 'add') gl.blendFunc(gl.ONE, gl.ONE);
      else if (blend === 'multiply') gl.blendFuncSeparate(gl.DST_COLOR, gl.ONE_MINUS_SRC_ALPHA, gl.ONE, gl.ONE_MINUS_SRC_ALPHA);
      else gl.blendFunc(gl.ONE, gl.ONE_MINUS_SRC_ALPHA);
      return 0;
    }
    if (blend === 'add') gl.blendFunc(gl.SRC_ALPHA, gl.ONE);
    else if (blend === 'multiply') gl.blendFunc(gl.DST_COLOR, gl.ONE_MINUS_SRC_ALPHA);
    else gl.blendFuncSeparate(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA, gl.ONE, gl.ONE_MINUS_SRC_ALPHA);
    return blend === 'multiply' ? 1 : 0;
  }

  // The frame's vertex and index buffers (a VAO of their own: 9 floats a
  // vertex, or with colorByte 5 floats and 4 colour bytes, as setMeshes
  // lays out the static vertices), grown to the largest frame so far and
  // then only overwritten.
  #uploadFrame(frame, colorByte) {
    const gl = this.gl;
    const bytes = !!colorByte;
    if (!this.frameVao) {
      this.frameVao = gl.createVertexArray();
      this.frameVbo = gl.createBuffer();
      this.frameIbo = gl.createBuffer();
      this.frameCapacity = [0, 0];
      this.frameBytes = null; // the layout the VAO holds
      gl.bindVertexArray(this.frameVao);
      gl.bindBuffer(gl.ARRAY_BUFFER, this.frameVbo);
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.frameIbo);
    }
    gl.bindVertexArray(this.frameVao);
    gl.bindBuffer(gl.ARRAY_BUFFER, this.frameVbo);
    if (this.frameBytes !== bytes) {
      setVertexLayout(gl, bytes);
      this.frameBytes = bytes;
    }
    // Pixi quantises a sprite's tint and alpha to bytes (pixiColorByte):
    // the frame's float colours become the same bytes, in a staging buffer
    // kept at the largest frame's size (nothing allocated per frame after).
    let vertices = frame.vertices;
    if (bytes) {
      const n = frame.vertices.length / VERTEX_FLOATS;
      if (!this.frameStaging || this.frameStaging.byteLength < n * 24) {
        this.frameStaging = new ArrayBuffer(n * 24 * 2);
        this.frameStagingF32 = new Float32Array(this.frameStaging);
        this.frameStagingU8 = new Uint8Array(this.frameStaging);
      }
      packVertices(frame.vertices, this.frameStagingF32, this.frameStagingU8, 0, colorByte);
      vertices = this.frameStagingU8.subarray(0, n * 24);
    }
    const cap = this.frameCapacity;
    if (vertices.byteLength > cap[0]) gl.bufferData(gl.ARRAY_BUFFER, (cap[0] = vertices.byteLength * 2), gl.STREAM_DRAW);
    if (frame.indices.byteLength > cap[1]) gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, (cap[1] = frame.indices.byteLength * 2), gl.STREAM_DRAW);
    if (vertices.length) gl.bufferSubData(gl.ARRAY_BUFFER, 0, vertices);
    if (frame.indices.length) gl.bufferSubData(gl.ELEMENT_ARRAY_BUFFER, 0, frame.indices);
  }

  /**
   * Draws the meshes into the bound framebuffer. `matrix`: a column-major
   * mat3 (Float32Array(9)) from world pixels to clip space, or `camera`
   * {x, y, width, height} (cameraMatrix). `clearDepth` (default true) clears
   * the depth buffer to 0 first. Returns this frame's {draws, triangles}.
   *
   * `frame`: moving sprites (FrameAssembler.assemble's result, src/frames.js)
   * drawn with the static meshes as runtime::Renderer::draw_frame draws
   * them: the frame's opaque draws first (its sprites lie in front of the
   * static levels below their points and behind those above: the depth test
   * sorts it), then the static opaque pass, then the static blend draws with
   * each insertion point's blend draws before the static draw it names.
   * Its draws name `frameTextures` (default the meshes' textures).
   * `frameColorByte(c, channel)`: the frame's colours as these bytes (as
   * setMeshes' colorByte; PixiJS quantises a sprite's tint and alpha so),
   * else as floats.
   * Without static meshes (setMeshes not called) only the frame is drawn.
   */
  draw({ matrix, camera, clearDepth = true, frame, frameTextures, frameColorByte } = {}) {
    const gl = this.gl;
    const m = matrix ?? cameraMatrix(camera ?? this.meshes?.viewport);
    const stats = { draws: 0, triangles: 0 };
    const saved = this.#save();
    const useDepth = this.depthTest || (frame ? frame.depthTest && frame.opaqueDraws > 0 : false);
    const texturesOfFrame = frameTextures ?? this.textures;
    let lastMode = -1;
    const drawOne = (texture, pass, blend, first, count) => {
      if (count === 0) return;
      const mode = pass === 'opaque' ? (blend === 'opaque' ? 2 : 0) : this.#blend(blend);
      if (mode !== lastMode) gl.uniform1i(this.uMode, (lastMode = mode));
      gl.bindTexture(gl.TEXTURE_2D, texture ?? null);
      gl.drawElements(gl.TRIANGLES, count, gl.UNSIGNED_INT, first * 4);
      stats.draws += 1;
      stats.triangles += count / 3;
    };
    const frameDraws = (from, to) => {
      if (from >= to) return;
      gl.bindVertexArray(this.frameVao);
      const d = frame.draws;
      for (let k = from; k < to; ++k) {
        const w = 5 * k;
        drawOne(texturesOfFrame[d[w]], d[w + 1] === 0 ? 'opaque' : 'blend', BLEND_NAMES[d[w + 2]], d[w + 3], d[w + 4]);
      }
      gl.bindVertexArray(this.vao);
    };
    let nextStatic = 0; // the static draws' blend pass cursor
    const staticBlendUntil = (end) => {
      for (; nextStatic < Math.min(end, this.draws.length); ++nextStatic) {
        const d = this.draws[nextStatic];
        if (d.pass === 'blend') drawOne(this.textures[d.image], 'blend', d.blend, d.first, d.count);
      }
    };
    try {
      gl.useProgram(this.program);
      gl.uniformMatrix3fv(this.uMatrix, false, m);
      gl.uniform1i(this.uTexture, 0);
      gl.uniform1i(this.uPremultiply, this.premultipliedAlpha ? 1 : 0);
      gl.bindSampler(0, null);
      gl.disable(gl.CULL_FACE); // mirrored elements have the other winding
      if (frame) this.#uploadFrame(frame, frameColorByte);
      gl.bindVertexArray(this.vao);
      if (clearDepth) {
        gl.depthMask(true);
        gl.clearDepth(0);
        gl.clear(gl.DEPTH_BUFFER_BIT);
      }
      if (useDepth) {
        gl.enable(gl.DEPTH_TEST);
        gl.depthFunc(gl.GREATER);
      } else {
        gl.disable(gl.DEPTH_TEST);
      }
      gl.depthMask(true);
      gl.disable(gl.BLEND);
      if (frame) frameDraws(0, frame.opaqueDraws);
      for (const d of this.draws) if (d.pass === 'opaque') drawOne(this.textures[d.image], 'opaque', d.blend, d.first, d.count);
      gl.depthMask(false);
      if (frame)
        for (let p = 0; p < frame.pointCount; ++p) {
          staticBlendUntil(frame.points[3 * p]);
          frameDraws(frame.points[3 * p + 1], frame.points[3 * p + 2]);
        }
      staticBlendUntil(this.draws.length);
    } finally {
      this.#restore(saved);
    }
    this.stats = stats;
    return stats;
  }

  destroy() {
    const gl = this.gl;
    gl.deleteProgram(this.program);
    gl.deleteVertexArray(this.vao);
    gl.deleteBuffer(this.vbo);
    gl.deleteBuffer(this.ibo);
    if (this.frameVao) {
      gl.deleteVertexArray(this.frameVao);
      gl.deleteBuffer(this.frameVbo);
      gl.deleteBuffer(this.frameIbo);
    }
  }
}
