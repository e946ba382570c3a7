// One triangle that covers the whole viewport; no vertex buffer needed.
// gl_VertexID 0, 1, 2 -> clip (-1,-1), (3,-1), (-1,3).
void main() {
    vec2 corner = vec2(float((gl_VertexID & 1) << 2), float((gl_VertexID & 2) << 1)) - 1.0;
    gl_Position = vec4(corner, 0.0, 1.0);
}
