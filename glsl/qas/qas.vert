#version 450
// QAS patches read their records in the tessellation stages: no per-vertex data.
void main() {
}
