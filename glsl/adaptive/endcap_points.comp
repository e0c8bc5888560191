#version 450
// Control points of the adaptive scheme's end caps: row first + i of the stencil rows
// (stencil_rows.glsl; 36 per end cap: the Gregory points, then the neighbours' edge and face
// points, gregory/gregory.glsl) into out_a[i]. Run first over the vertex-point rows (the first
// stage, out_a the vertex points), then over the end caps' rows, which read them.
#include "stencil_rows.glsl"

void main() {
    uint i = item();
    if (i == NO_ROW) {
        return;
    }
    out_a[i] = vec4(row_sum(range.first + i), 1.0);
}
