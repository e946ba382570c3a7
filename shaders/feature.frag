// Stores the feature surface for the composite pass: normal xy, height, coverage.
// An RGBA8 target renders on every OpenGL ES 3.0 device (float targets need an extension).
// EDGE_AA (the glass look): each face falls to the glass along the ridge's edge, so its
// height over the height's screen gradient (L1: how far a pixel's box reaches across an
// edge) says how far inside the edge the pixel's centre lies. Within half a px of the
// edge the pixel stores the share of it the ridge covers and the ridge's mean height
// over it (the composite pass scales height and slope by the coverage); the faces run
// on below the glass for the pixels whose centre lies just outside.
uniform float u_height_scale; // height that maps to 1.0, px

in vec3 v_normal;
in float v_height;

out vec4 out_color;

void main() {
    vec3 n = normalize(v_normal);
#ifdef EDGE_AA
    float ramp = max(abs(dFdx(v_height)) + abs(dFdy(v_height)), 1e-6);
    float inside = v_height / ramp;  // px from the edge, along the pixel's diagonal reach
    float cover = clamp(inside + 0.5, 0.0, 1.0);
    if (cover <= 0.0) {
        discard;  // beyond the edge's reach: leave what lies below
    }
    // Mean height over the pixel: ramp * cover^2 / 2 by the edge, stored over cover.
    float h = inside < 0.5 ? 0.5 * ramp * cover : v_height;
    out_color = vec4(n.xy * 0.5 + 0.5, clamp(h / u_height_scale, 0.0, 1.0), cover);
#else
    out_color = vec4(n.xy * 0.5 + 0.5, clamp(v_height / u_height_scale, 0.0, 1.0), 1.0);
#endif
}
