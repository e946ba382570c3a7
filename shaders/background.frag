// The view through the window: the background image, pixel for pixel.
uniform sampler2D u_background; // screen-sized, row 0 = top of the screen
uniform vec2 u_screen;          // width, height, px

out vec4 out_color;

void main() {
    ivec2 pix = ivec2(gl_FragCoord.xy);
    out_color = vec4(texelFetch(u_background, ivec2(pix.x, int(u_screen.y) - 1 - pix.y), 0).rgb, 1.0);
}
