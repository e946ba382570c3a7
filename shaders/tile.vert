// A screen tile that holds ice, instanced: only those tiles run the ice shader,
// so clear glass costs nothing beyond the background pass.
uniform vec2 u_screen;    // width, height, px
uniform float u_tile;     // tile side, px

in vec2 in_corner;        // per vertex: 0 or 1 in x and y
in vec2 in_tile;          // per instance: tile column, row (row 0 = top)

void main() {
    vec2 p = (in_tile + in_corner) * u_tile;  // screen px, y down
    p = min(p, u_screen);
    gl_Position = vec4(p.x / u_screen.x * 2.0 - 1.0, 1.0 - p.y / u_screen.y * 2.0, 0.0, 1.0);
}
