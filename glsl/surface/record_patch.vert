#version 450
// Passes whose tessellation stages read per-patch records written by the host (render::pass::
// records: QAS, ACC): one-point patches, no per-vertex data.
void main() {
}
