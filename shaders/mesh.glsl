#version 330 core
// Vertex-coloured or textured mesh under a key and a fill light, fixed to the camera so every
// view is lit alike. Colours arrive as sRGB bytes; lighting happens in linear light and the
// result is encoded back to sRGB for the 8-bit framebuffer.
//
// Lighting runs per vertex: a captured body has ~17,000 vertices, so at playback sizes its
// triangles cover a pixel or two and per-vertex lighting looks the same as per-pixel, while it
// costs far less (software GL shades every fragment on the CPU).
// Define FACET_NORMALS when the source gives no vertex normals: each triangle is then lit flat,
// per fragment, from screen-space derivatives.
// Define TEXTURED to colour the surface from the frame's texture (``albedo_map``, sampled at
// ``in_uv``, v = 0 at the image's bottom row) instead of the vertex colours: text on a card held
// up to a depth camera stays readable, which vertex colours blur away. The light is still
// computed per vertex and applied to each texel.
// Define MOVING to draw the surface at fraction ``instant`` of a step to the next frame shown:
// each vertex moves by ``instant`` times its displacement ``in_offset`` (half floats), so the
// body moves at the display's rate while the frame's arrays are uploaded once per step
// (``tvmedit.engine.inbetween.instants``).

// Camera space, pointing towards the lights. A face looking straight at the camera receives
// ambient + key + fill of about 1.0, so it shows its stored colour.
const vec3 KEY_DIRECTION = normalize(vec3(-0.4, 0.6, 0.7));
const vec3 FILL_DIRECTION = normalize(vec3(0.6, -0.2, 0.8));
const float KEY = 0.8;
const float FILL = 0.35;
const float AMBIENT = 0.2;

vec3 srgb_to_linear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), step(0.04045, c));
}

vec3 linear_to_srgb(vec3 c) {
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

// How much light reaches a surface point: unit normal and position, both in camera space.
float lighting(vec3 n, vec3 position) {
    // Two-sided: reconstructed meshes have holes, flipped and noisy normals, so always light
    // the side that faces the viewer.
    if (dot(n, position) > 0.0) n = -n;
    return AMBIENT + KEY * max(dot(n, KEY_DIRECTION), 0.0) + FILL * max(dot(n, FILL_DIRECTION), 0.0);
}

// sRGB colour of a surface point: linear albedo, unit normal and position, both in camera space.
vec3 shade(vec3 albedo, vec3 n, vec3 position) {
    return linear_to_srgb(clamp(albedo * lighting(n, position), 0.0, 1.0));
}

#if defined VERTEX_SHADER

uniform mat4 view;
uniform mat4 projection;

in vec3 in_position;
#ifdef MOVING
uniform float instant;
in vec3 in_offset;
#endif
#ifdef TEXTURED
in vec2 in_uv;
out vec2 v_uv;
out float v_light;
#else
in vec3 in_colour;
out vec3 v_colour;
#endif
#ifdef FACET_NORMALS
out vec3 v_position;
#else
in vec3 in_normal;
#endif

void main() {
#ifdef MOVING
    vec4 p = view * vec4(in_position + instant * in_offset, 1.0);
#else
    vec4 p = view * vec4(in_position, 1.0);
#endif
#ifdef TEXTURED
    v_uv = in_uv;
#endif
#ifdef FACET_NORMALS
    v_position = p.xyz;
#ifndef TEXTURED
    v_colour = srgb_to_linear(in_colour);
#endif
#else
    // The view matrix is a rotation plus a translation, so its upper 3x3 carries normals too.
    // A vertex whose faces cancel has a zero normal: light it as if it faced the camera.
    vec3 n = mat3(view) * in_normal;
    n = dot(n, n) > 1e-12 ? normalize(n) : -normalize(p.xyz);
#ifdef TEXTURED
    v_light = lighting(n, p.xyz);
#else
    v_colour = shade(srgb_to_linear(in_colour), n, p.xyz);
#endif
#endif
    gl_Position = projection * p;
}

#elif defined FRAGMENT_SHADER

#ifdef TEXTURED
uniform sampler2D albedo_map;
in vec2 v_uv;
in float v_light;
#else
in vec3 v_colour;
#endif
#ifdef FACET_NORMALS
in vec3 v_position;
#endif
out vec4 frag_colour;

void main() {
#ifdef TEXTURED
    // Texture rows are uploaded top first, so the image's top row lies at t = 0.
    vec3 albedo = srgb_to_linear(texture(albedo_map, vec2(v_uv.x, 1.0 - v_uv.y)).rgb);
#ifdef FACET_NORMALS
    float light = lighting(normalize(cross(dFdx(v_position), dFdy(v_position))), v_position);
#else
    float light = v_light;
#endif
    frag_colour = vec4(linear_to_srgb(clamp(albedo * light, 0.0, 1.0)), 1.0);
#else
#ifdef FACET_NORMALS
    frag_colour = vec4(shade(v_colour, normalize(cross(dFdx(v_position), dFdy(v_position))), v_position), 1.0);
#else
    frag_colour = vec4(v_colour, 1.0);
#endif
#endif
}

#endif
