// Stores the feature surface for the composite pass: normal xy, height, coverage.
// An RGBA8 target renders on every OpenGL ES 3.0 device (float targets need an extension).
uniform float u_height_scale; // height that maps to 1.0, px

in vec3 v_normal;
in float v_height;

out vec4 out_color;

void main() {
    vec3 n = normalize(v_normal);
    out_color = vec4(n.xy * 0.5 + 0.5, clamp(v_height / u_height_scale, 0.0, 1.0), 1.0);
}
