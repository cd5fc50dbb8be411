#version 330 core
// Vertex-coloured mesh under a key and a fill light, fixed to the camera so every view is lit
// alike. Colours arrive as sRGB bytes; lighting happens in linear light and the result is
// encoded back to sRGB for the 8-bit framebuffer.
//
// Lighting runs per vertex: a captured body has ~17,000 vertices, so at playback sizes its
// triangles cover a pixel or two and per-vertex lighting looks the same as per-pixel, while it
// costs far less (software GL shades every fragment on the CPU).
// Define FACET_NORMALS when the source gives no vertex normals: each triangle is then lit flat,
// per fragment, from screen-space derivatives.

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

// sRGB colour of a surface point: linear albedo, unit normal and position, both in camera space.
vec3 shade(vec3 albedo, vec3 n, vec3 position) {
    // Two-sided: reconstructed meshes have holes, flipped and noisy normals, so always light
    // the side that faces the viewer.
    if (dot(n, position) > 0.0) n = -n;
    float light = AMBIENT + KEY * max(dot(n, KEY_DIRECTION), 0.0) + FILL * max(dot(n, FILL_DIRECTION), 0.0);
    return linear_to_srgb(clamp(albedo * light, 0.0, 1.0));
}

#if defined VERTEX_SHADER

uniform mat4 view;
uniform mat4 projection;

in vec3 in_position;
in vec3 in_colour;
out vec3 v_colour;
#ifdef FACET_NORMALS
out vec3 v_position;
#else
in vec3 in_normal;
#endif

void main() {
    vec4 p = view * vec4(in_position, 1.0);
#ifdef FACET_NORMALS
    v_position = p.xyz;
    v_colour = srgb_to_linear(in_colour);
#else
    // The view matrix is a rotation plus a translation, so its upper 3x3 carries normals too.
    // A vertex whose faces cancel has a zero normal: light it as if it faced the camera.
    vec3 n = mat3(view) * in_normal;
    n = dot(n, n) > 1e-12 ? normalize(n) : -normalize(p.xyz);
    v_colour = shade(srgb_to_linear(in_colour), n, p.xyz);
#endif
    gl_Position = projection * p;
}

#elif defined FRAGMENT_SHADER

in vec3 v_colour;
#ifdef FACET_NORMALS
in vec3 v_position;
#endif
out vec4 frag_colour;

void main() {
#ifdef FACET_NORMALS
    frag_colour = vec4(shade(v_colour, normalize(cross(dFdx(v_position), dFdy(v_position))), v_position), 1.0);
#else
    frag_colour = vec4(v_colour, 1.0);
#endif
}

#endif
