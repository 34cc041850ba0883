// The runtime's sprite shader: texture x vertex colour, nothing else (no
// discard, which would switch off early depth rejection, the point of the
// opaque pass). One source for both targets: the version header picks
// GLSL 3.30 core or GLSL ES 3.00, and a define per blend mode picks the
// output.
#pragma once

namespace depthcull::runtime {

inline constexpr const char* kDesktopHeader = "#version 330 core\n";
inline constexpr const char* kEsHeader = "#version 300 es\nprecision highp float;\n";

// World pixels to clip space: u_camera = (x, y) of the view's top-left and
// u_scale = (2 / width, +-2 / height), u_offset = (-1, +-1): the sign picks
// whether world y grows up or down the framebuffer (Camera::flip_y). z in
// 0..1, larger nearer, to clip -1..1 (window depth = z with the default
// depth range).
inline constexpr const char* kVertexShader = R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec2 a_uv;
layout(location = 2) in vec4 a_color;
uniform vec4 u_camera;
uniform vec4 u_scale_offset;
out vec2 v_uv;
out vec4 v_color;
void main() {
    vec2 p = (a_position.xy - u_camera.xy) * u_scale_offset.xy + u_scale_offset.zw;
    gl_Position = vec4(p, a_position.z * 2.0 - 1.0, 1.0);
    v_uv = a_uv;
    v_color = a_color;
}
)";

// The fragment shader up to its colour `c`; kBlendTail finishes it.
inline constexpr const char* kFragmentShader = R"(
uniform sampler2D u_texture;
in vec2 v_uv;
in vec4 v_color;
out vec4 o_color;
void main() {
    vec4 c = texture(u_texture, v_uv) * v_color;
)";

// The end of every depthcull fragment shader (this one and render's),
// one define per Blend (kBlendDefines). Texels are not premultiplied
// (PNG's). BLEND_MULTIPLY premultiplies, so the blend (GL_DST_COLOR,
// GL_ONE_MINUS_SRC_ALPHA) gives dst * (src.rgb * src.a + 1 - src.a): a
// transparent texel leaves dst as it is. BLEND_OPAQUE writes alpha 1
// (blending is off for it; the texel's alpha is ignored, the whole rect
// is opaque).
inline constexpr const char* kBlendTail = R"(
#if defined(BLEND_MULTIPLY)
    c.rgb *= c.a;
#elif defined(BLEND_OPAQUE)
    c.a = 1.0;
#endif
    o_color = c;
}
)";

// Indexed by int(Blend): alpha, add, multiply, opaque.
inline constexpr const char* kBlendDefines[] = {"", "", "#define BLEND_MULTIPLY 1\n", "#define BLEND_OPAQUE 1\n"};

} // namespace depthcull::runtime
