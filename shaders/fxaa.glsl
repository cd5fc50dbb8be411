#version 330 core
// Fast approximate anti-aliasing: one fullscreen pass over the finished scene that softens the
// pixels on silhouettes and colour edges. It is the local ("subpixel") stage of Timothy Lottes'
// FXAA 3.11 quality, without its search along each edge for the edge's ends:
//
// * a pixel is on an edge when the luma range of it and its four neighbours exceeds
//   max(EDGE_THRESHOLD_MIN, EDGE_THRESHOLD * brightest), as in FXAA;
// * it is blended towards its neighbours' mean by how far its luma stands out from that mean,
//   relative to the range (smoothstep'ed, as FXAA's subpixel term): a pixel on a straight edge
//   moves little, the corner of a stair step or a lone pixel much.
//
// Why so little: this pass exists for software rasterisers (llvmpipe), which run both sides of
// every branch for a block of pixels while any of them needs one, so FXAA's early exit on flat
// areas saves nothing, and where a bilinear tap costs about five texelFetch. Measured on a
// 640x480 frame that bare drawing renders in ~6.7 ms (2 cores): FXAA 3.11 console (nine bilinear
// taps) added ~8.5 ms, a plain one-texelFetch copy ~1.2 ms, this pass (five texelFetch) ~2.5 ms.
// The price is quality: long, nearly straight edges keep steps that FXAA's search would ramp
// out; stair corners and curved silhouettes are smoothed.
//
// Only pixels with the mesh among the five are blended: the scene's alpha is 1 on the mesh and
// 0 elsewhere (the floor grid draws its lines anti-aliased and leaves alpha alone), so the
// renderer may run this pass over the mesh's box on screen alone.
//
// The scene holds sRGB-encoded colour, the perceptual scale FXAA is tuned for. Luma comes from all
// three channels (not green alone, as FXAA may), so a red figure on the dark grey background
// still shows an edge. The pass copies without flipping.

#if defined VERTEX_SHADER

// One triangle covering the viewport, from gl_VertexID alone (no vertex buffer):
// (-1, -1), (3, -1), (-1, 3).
void main() {
    vec2 corner = vec2(float((gl_VertexID & 1) << 2), float((gl_VertexID & 2) << 1)) - 1.0;
    gl_Position = vec4(corner, 0.0, 1.0);
}

#elif defined FRAGMENT_SHADER

uniform sampler2D scene;  // sized like the output's viewport
uniform ivec2 origin;     // the output viewport's lower-left corner, pixels

out vec4 frag_colour;

const float EDGE_THRESHOLD = 0.125;     // FXAA "high quality"
const float EDGE_THRESHOLD_MIN = 0.0312;
const float STRENGTH = 0.8;             // blend of the most outstanding pixel towards its neighbours

float luma(vec3 rgb) {
    return dot(rgb, vec3(0.299, 0.587, 0.114));
}

void main() {
    ivec2 last = textureSize(scene, 0) - 1;
    ivec2 p = ivec2(gl_FragCoord.xy) - origin;
    // Clamped: a texelFetch outside the texture is undefined.
    vec4 m4 = texelFetch(scene, p, 0);
    vec4 n4 = texelFetch(scene, ivec2(p.x, min(p.y + 1, last.y)), 0);
    vec4 s4 = texelFetch(scene, ivec2(p.x, max(p.y - 1, 0)), 0);
    vec4 e4 = texelFetch(scene, ivec2(min(p.x + 1, last.x), p.y), 0);
    vec4 w4 = texelFetch(scene, ivec2(max(p.x - 1, 0), p.y), 0);
    vec3 m = m4.rgb, n = n4.rgb, s = s4.rgb, e = e4.rgb, w = w4.rgb;
    // Alpha marks the mesh; pixels with no mesh among the five stay as drawn.
    bool near_mesh = max(max(max(n4.a, s4.a), max(e4.a, w4.a)), m4.a) > 0.5;
    float luma_m = luma(m), luma_n = luma(n), luma_s = luma(s), luma_e = luma(e), luma_w = luma(w);

    float luma_max = max(max(max(luma_n, luma_s), max(luma_e, luma_w)), luma_m);
    float luma_min = min(min(min(luma_n, luma_s), min(luma_e, luma_w)), luma_m);
    float range = luma_max - luma_min;
    float stand_out = abs(0.25 * (luma_n + luma_s + luma_e + luma_w) - luma_m) / max(range, 1e-4);
    float blend = !near_mesh || range < max(EDGE_THRESHOLD_MIN, EDGE_THRESHOLD * luma_max) ? 0.0 : smoothstep(0.0, 1.0, stand_out);
    frag_colour = vec4(mix(m, 0.25 * (n + s + e + w), STRENGTH * blend), 1.0);
}

#endif
