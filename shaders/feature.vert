// Sharp-feature triangles (Fig. 6) in screen px (x right, y down, z toward the viewer)
// rasterized once into the persistent ice texture.
// EDGE_AA (the glass look): a ridge's faces run on past its edge, below the glass, to
// reach the pixels its edge crosses; their depth must still pass against the clear 1.0.
uniform vec2 u_screen;     // width, height of the screen, px
uniform float u_max_depth; // heights at or above this share the nearest depth, px

in vec3 in_position;
in vec3 in_normal;

out vec3 v_normal;
out float v_height;

void main() {
    vec2 ndc = vec2(in_position.x / u_screen.x * 2.0 - 1.0, 1.0 - in_position.y / u_screen.y * 2.0);
    // Higher surfaces get smaller depth, so with a LESS test the top one wins.
#ifdef EDGE_AA
    float depth = -clamp(in_position.z / u_max_depth, -1.0, 1.0);
#else
    float depth = 1.0 - 2.0 * clamp(in_position.z / u_max_depth, 0.0, 1.0);
#endif
    gl_Position = vec4(ndc, depth, 1.0);
    v_normal = in_normal;
    v_height = in_position.z;
}
