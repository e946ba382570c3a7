// The frame: background seen through the glass, then the ice (bumpy surface of Fig. 7
// plus sharp features of Fig. 6), alpha-blended by thickness and Phong-shaded.
uniform sampler2D u_background; // screen-sized, row 0 = top of the screen
uniform sampler2D u_heights;    // height grid, one texel per vertex, bilinear
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
uniform float u_density;        // opacity per px of thickness: 1 - exp(-density * t)
uniform float u_relief;         // slope exaggeration for shading
uniform float u_refraction;     // background offset per unit of normal tilt, px

out vec4 out_color;

// Height and slope of the bumpy surface, bilinear between grid vertices;
// slope by central differences one vertex apart.
vec3 bump_surface(vec2 p) {
    vec2 texel = 1.0 / u_grid_size;
    vec2 uv = (p / u_spacing + 0.5) * texel;
    float h = texture(u_heights, uv).r;
    float hx = texture(u_heights, uv + vec2(texel.x, 0.0)).r - texture(u_heights, uv - vec2(texel.x, 0.0)).r;
    float hy = texture(u_heights, uv + vec2(0.0, texel.y)).r - texture(u_heights, uv - vec2(0.0, texel.y)).r;
    return vec3(h, vec2(hx, hy) / (2.0 * u_spacing));
}

// Height and slope of the feature surface: a plane with normal n has slope -n.xy / n.z.
vec3 feature_surface(ivec2 pix) {
    vec4 f = texelFetch(u_ice, pix, 0);
    vec2 nxy = f.rg * 2.0 - 1.0;
    float nz = sqrt(max(1.0 - dot(nxy, nxy), 0.04));
    return f.a * vec3(f.b * u_height_scale, -nxy / nz);
}

vec3 background(vec2 p) {
    ivec2 size = textureSize(u_background, 0);
    ivec2 q = clamp(ivec2(p), ivec2(0), size - 1);
    return texelFetch(u_background, q, 0).rgb;
}

void main() {
    vec2 p = vec2(gl_FragCoord.x, u_screen.y - gl_FragCoord.y); // screen px, y down
    vec3 s = u_show_bumps * bump_surface(p) + u_show_features * feature_surface(ivec2(gl_FragCoord.xy));
    float thickness = s.x;
    // Surfaces add up: z = hb + hf, so their slopes add; normal = (-slope, 1).
    vec3 n = normalize(vec3(-u_relief * s.yz, 1.0));
    float alpha = u_opacity * (1.0 - exp(-u_density * thickness));
    // Phong with the viewer straight ahead (orthographic): ambient + diffuse + specular.
    vec3 r = reflect(-u_light, n);
    float diffuse = max(dot(n, u_light), 0.0);
    float specular = pow(max(r.z, 0.0), u_shininess);
    vec3 lit = u_ice_color * (u_ambient + u_diffuse * diffuse);
    // Tilted ice bends the view of the background a little (a cheap refraction).
    vec3 behind = background(p + u_refraction * n.xy);
    vec3 color = mix(behind, lit, alpha) + u_specular * specular * alpha / u_opacity;
    out_color = vec4(color, 1.0);
}
