// The ice over the background: bumpy surface (Fig. 7) plus sharp features (Fig. 6),
// Phong-shaded, written premultiplied for blending with (ONE, ONE_MINUS_SRC_ALPHA):
// frame = ice + (1 - alpha) * background, so clear glass (alpha 0) leaves the view as is.
uniform sampler2D u_heights;    // height grid: height, slope x, slope y per vertex, bilinear
uniform sampler2D u_ice;        // feature surface (feature.frag), row 0 = bottom
uniform vec2 u_screen;          // width, height, px
uniform vec2 u_grid_size;       // columns, rows of the height grid
uniform float u_spacing;        // grid spacing, px
uniform float u_height_scale;   // feature height that u_ice stores as 1.0, px
uniform float u_show_bumps;     // 1.0 or 0.0
uniform float u_show_features;  // 1.0 or 0.0
uniform vec3 u_light;           // unit vector toward the light (x right, y down, z to viewer)
uniform vec3 u_ice_color;
uniform float u_ambient;
uniform float u_diffuse;
uniform float u_specular;
uniform float u_shininess;
uniform float u_opacity;        // opacity of very thick ice
uniform float u_density;        // alpha = opacity * (1 - exp(-density * thickness))
uniform float u_relief;         // slope exaggeration for shading

out vec4 out_color;

// Height and slope of the bumpy surface, bilinear between grid vertices.
vec3 bump_surface(vec2 p) {
    return texture(u_heights, (p / u_spacing + 0.5) / u_grid_size).rgb;
}

// Height and slope of the feature surface: a plane with normal n has slope -n.xy / n.z.
vec3 feature_surface(ivec2 pix) {
    vec4 f = texelFetch(u_ice, pix, 0);
    vec2 nxy = f.rg * 2.0 - 1.0;
    float nz = sqrt(max(1.0 - dot(nxy, nxy), 0.04));
    return f.a * vec3(f.b * u_height_scale, -nxy / nz);
}

void main() {
    vec2 p = vec2(gl_FragCoord.x, u_screen.y - gl_FragCoord.y); // screen px, y down
    vec3 s = u_show_bumps * bump_surface(p) + u_show_features * feature_surface(ivec2(gl_FragCoord.xy));
    // Surfaces add up: z = hb + hf, so their slopes add; normal = (-slope, 1).
    vec3 n = normalize(vec3(-u_relief * s.yz, 1.0));
    float alpha = u_opacity * (1.0 - exp(-u_density * max(s.x, 0.0)));
    // Phong with the viewer straight ahead (orthographic): ambient + diffuse + specular.
    float diffuse = max(dot(n, u_light), 0.0);
    float specular = pow(max(reflect(-u_light, n).z, 0.0), u_shininess);
    vec3 lit = u_ice_color * (u_ambient + u_diffuse * diffuse);
    // Glints scale with alpha / opacity so that they fade out with the ice at its rim.
    out_color = vec4(alpha * lit + u_specular * specular * alpha / u_opacity, alpha);
}
