#version 330 core
// Vertex-coloured mesh under a key and a fill light, fixed to the camera so every view is lit
// alike. Colours arrive as sRGB bytes; lighting happens in linear light and the result is
// encoded back to sRGB for the 8-bit framebuffer.
// Define FACET_NORMALS when the source gives no vertex normals: the fragment stage then shades
// each triangle flat from screen-space derivatives.

#if defined VERTEX_SHADER

uniform mat4 view;
uniform mat4 projection;

in vec3 in_position;
in vec3 in_colour;
#ifndef FACET_NORMALS
in vec3 in_normal;
out vec3 v_normal;
#endif
out vec3 v_position;
out vec3 v_colour;

vec3 srgb_to_linear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), step(0.04045, c));
}

void main() {
    vec4 p = view * vec4(in_position, 1.0);
    v_position = p.xyz;
#ifndef FACET_NORMALS
    // The view matrix is a rotation plus a translation, so its upper 3x3 carries normals too.
    v_normal = mat3(view) * in_normal;
#endif
    // Linearised per vertex so that interpolation across a triangle also happens in linear light.
    v_colour = srgb_to_linear(in_colour);
    gl_Position = projection * p;
}

#elif defined FRAGMENT_SHADER

// Camera space, pointing towards the lights. A face looking straight at the camera receives
// ambient + key + fill of about 1.0, so it shows its stored colour.
const vec3 KEY_DIRECTION = normalize(vec3(-0.4, 0.6, 0.7));
const vec3 FILL_DIRECTION = normalize(vec3(0.6, -0.2, 0.8));
const float KEY = 0.8;
const float FILL = 0.35;
const float AMBIENT = 0.2;

in vec3 v_position;
in vec3 v_colour;
#ifndef FACET_NORMALS
in vec3 v_normal;
#endif
out vec4 frag_colour;

vec3 linear_to_srgb(vec3 c) {
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

void main() {
    vec3 n = cross(dFdx(v_position), dFdy(v_position));
#ifndef FACET_NORMALS
    // Vertices no face uses, or whose faces cancel, have zero normals: keep the facet normal there.
    if (dot(v_normal, v_normal) > 1e-12) n = v_normal;
#endif
    n = normalize(n);
    // Two-sided: reconstructed meshes have holes, flipped and noisy normals, so always light
    // the side that faces the viewer.
    if (dot(n, v_position) > 0.0) n = -n;
    float light = AMBIENT + KEY * max(dot(n, KEY_DIRECTION), 0.0) + FILL * max(dot(n, FILL_DIRECTION), 0.0);
    frag_colour = vec4(linear_to_srgb(clamp(v_colour * light, 0.0, 1.0)), 1.0);
}

#endif
