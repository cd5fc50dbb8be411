#version 330 core
// Floor grid at z = 0: one square, lines drawn procedurally with screen-space widths so they stay
// one pixel thin and anti-aliased at any distance, fading out towards the square's edge.

#if defined VERTEX_SHADER

uniform mat4 view;
uniform mat4 projection;
uniform vec2 centre;      // metres, the square's centre on the floor
uniform float extent;     // metres, half the square's side

in vec2 in_corner;        // (-1, -1) .. (1, 1)
out vec2 v_floor;

void main() {
    v_floor = centre + in_corner * extent;
    gl_Position = projection * view * vec4(v_floor, 0.0, 1.0);
}

#elif defined FRAGMENT_SHADER

uniform vec2 centre;
uniform float extent;
uniform float spacing;    // metres between lines
uniform vec3 line_colour; // sRGB

in vec2 v_floor;
out vec4 frag_colour;

void main() {
    vec2 cell = v_floor / spacing;
    vec2 to_line = abs(fract(cell - 0.5) - 0.5) / fwidth(cell);
    float line = 1.0 - min(min(to_line.x, to_line.y), 1.0);
    float fade = 1.0 - smoothstep(0.5 * extent, extent, length(v_floor - centre));
    frag_colour = vec4(line_colour, 0.6 * line * fade);
}

#endif
