#version 330 core
// Flat-coloured 2D shapes in pixel coordinates (the inspector's timeline): rectangles as
// triangles and the atom-distance curve as a line strip, each vertex with its own colour.

#if defined VERTEX_SHADER

uniform vec2 screen;     // framebuffer size, pixels

in vec2 in_pixel;        // pixels from the top-left corner
in vec4 in_colour;       // sRGB and alpha, 0..1
out vec4 v_colour;

void main() {
    v_colour = in_colour;
    gl_Position = vec4(in_pixel.x / screen.x * 2.0 - 1.0, 1.0 - in_pixel.y / screen.y * 2.0, 0.0, 1.0);
}

#elif defined FRAGMENT_SHADER

in vec4 v_colour;
out vec4 frag_colour;

void main() {
    frag_colour = v_colour;
}

#endif
