#version 450
// End caps read their control points from a storage buffer (endcap_points.comp): the vertex
// stage has nothing to pass on.
void main() {
}
