// The ice over the background: bumpy surface (Fig. 7) plus sharp features (Fig. 6),
// Phong-shaded, written premultiplied for blending with (ONE, ONE_MINUS_SRC_ALPHA):
// frame = ice + (1 - alpha) * background, so clear glass (alpha 0) leaves the view as is.
// The glass look is chosen at compile time (a branch on a uniform runs both sides on
// llvmpipe): FILM cuts the bumps' skirt to a crisp rim, SCATTER whitens ice with its
// thickness and rims steep facets, SPARKLE breaks the glints into specks, REFRACT draws
// the view behind shifted by the ice's slope (and then writes the final colour).
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
#ifdef REFRACT
uniform sampler2D u_background; // screen-sized, row 0 = top of the screen
uniform float u_refraction;     // px the view shifts per unit slope in thick ice
#endif

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

// The bump surface as a film: below FILM_CUT px it is clear glass, above it rises
// FILM_GAIN times as fast, so the halo around every stem becomes a crisp rim.
#ifdef FILM
const float FILM_CUT = 0.8;
const float FILM_GAIN = 1.3;
vec3 film(vec3 s) {
    return s.x > FILM_CUT ? vec3(FILM_GAIN * (s.x - FILM_CUT), FILM_GAIN * s.yz) : vec3(0.0);
}
#endif

#ifdef SPARKLE
// A stable pseudo-random number in [0, 1) per pixel (interleaved gradient noise: no sin,
// which is slow on a CPU rasterizer).
float hash(vec2 p) {
    return fract(52.9829189 * fract(dot(p, vec2(0.06711056, 0.00583715))));
}
#endif

#if defined(SCATTER) || defined(SPARKLE) || defined(REFRACT)
// Shaded ice colour (not premultiplied) of thickness h with normal n.
vec3 shade(vec3 n, float h, float alpha) {
    float diffuse = max(dot(n, u_light), 0.0);
    float specular = pow(max(reflect(-u_light, n).z, 0.0), u_shininess);
    vec3 lit = u_ice_color * (u_ambient + u_diffuse * diffuse);
#ifdef SCATTER
    // Thin ice is clear with a cold tint, thick ice scatters white; steep facets rim.
    float white = 1.0 - exp(-0.35 * h);
    float steep = 1.0 - n.z;
    lit = mix(vec3(0.62, 0.76, 0.92), lit, white) + 0.35 * steep * steep;
    specular *= 0.45;
#endif
#ifdef SPARKLE
    // The sharp lobe broken into 1 px specks, and a few point glints in thick ice.
    float speck = hash(floor(gl_FragCoord.xy));
    specular *= step(0.55, speck) * 2.2;
    specular += step(0.985, speck) * step(2.0, h) * pow(max(dot(n, u_light), 0.0), 8.0) * 1.5;
#endif
    return lit + u_specular * specular / u_opacity;
}
#endif

void main() {
    vec2 p = vec2(gl_FragCoord.x, u_screen.y - gl_FragCoord.y); // screen px, y down
    vec3 bumps = bump_surface(p);
#ifdef FILM
    bumps = film(bumps);
#endif
    vec3 s = u_show_bumps * bumps + u_show_features * feature_surface(ivec2(gl_FragCoord.xy));
    float h = max(s.x, 0.0);
#ifdef REFRACT
    if (h <= 0.0) {
        out_color = vec4(0.0);  // clear glass: the background pass's pixel, exactly
        return;                 // (before any shading: a CPU rasteriser skips it all)
    }
#endif
    // Surfaces add up: z = hb + hf, so their slopes add; normal = (-slope, 1).
    vec3 n = normalize(vec3(-u_relief * s.yz, 1.0));
    float alpha = u_opacity * (1.0 - exp(-u_density * h));
#if defined(SCATTER) || defined(SPARKLE) || defined(REFRACT)
    vec3 ice = shade(n, h, alpha);
#ifdef REFRACT
    // The view through the ice, shifted by its slope, more in thicker ice (the nearest
    // texel: a bilinear read cost half again as much on llvmpipe, and a ridge's faces are
    // flat, so each shifts its view by one amount).
    vec2 shift = -u_refraction * s.yz * min(h / 3.0, 1.0);
    vec3 view = texelFetch(u_background, ivec2(clamp(p + shift, vec2(0.0), u_screen - 1.0)), 0).rgb;
    out_color = vec4(mix(view, ice, alpha), 1.0);
#else
    out_color = vec4(alpha * ice, alpha);
#endif
#else
    // Phong with the viewer straight ahead (orthographic): ambient + diffuse + specular.
    float diffuse = max(dot(n, u_light), 0.0);
    float specular = pow(max(reflect(-u_light, n).z, 0.0), u_shininess);
    vec3 lit = u_ice_color * (u_ambient + u_diffuse * diffuse);
    // Glints scale with alpha / opacity so that they fade out with the ice at its rim.
    out_color = vec4(alpha * lit + u_specular * specular * alpha / u_opacity, alpha);
#endif
}
