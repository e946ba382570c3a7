// Dear ImGui's draw lists: positions in window px (y down), texture coordinates, colours.
uniform vec2 u_display;  // the window's size in the draw lists' px
in vec2 in_position;
in vec2 in_uv;
in vec4 in_color;
out vec2 v_uv;
out vec4 v_color;

void main() {
    v_uv = in_uv;
    v_color = in_color;
    vec2 ndc = in_position / u_display * 2.0 - 1.0;
    gl_Position = vec4(ndc.x, -ndc.y, 0.0, 1.0);
}
