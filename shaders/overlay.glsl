#version 330 core
// On-screen text: textured quads in pixel coordinates over the scene. The atlas holds the
// bitmap font's glyphs as a one-channel coverage mask, plus one solid cell that backing boxes
// sample, so text and its boxes are drawn in one call.

#if defined VERTEX_SHADER

uniform vec2 screen;     // framebuffer size, pixels

in vec2 in_pixel;        // pixels from the top-left corner
in vec2 in_uv;           // atlas texel coordinates (0..1)
in vec4 in_colour;       // sRGB and alpha, 0..1
out vec2 v_uv;
out vec4 v_colour;

void main() {
    v_uv = in_uv;
    v_colour = in_colour;
    gl_Position = vec4(in_pixel.x / screen.x * 2.0 - 1.0, 1.0 - in_pixel.y / screen.y * 2.0, 0.0, 1.0);
}

#elif defined FRAGMENT_SHADER

uniform sampler2D atlas;

in vec2 v_uv;
in vec4 v_colour;
out vec4 frag_colour;

void main() {
    frag_colour = vec4(v_colour.rgb, v_colour.a * texture(atlas, v_uv).r);
}

#endif
