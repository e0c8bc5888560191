#version 450
// ACC geometry patch (acc.glsl): the bicubic Bézier patch inside; corners and edges by the
// shared watertight rules. Drawn whole. Defines: SPACING, CAPTURE.
#include "frame.glsl"
#include "watertight.glsl"
#include "acc.glsl"
#include "displace.glsl"
#ifdef CAPTURE
#include "capture.glsl"
#endif
#include "tes_outputs.glsl"

layout(quads, SPACING, cw) in;

/// Per edge k, its Bézier row and the row beside it inside the patch in the direction of the
/// edge's coordinate x (u on edges 0 and 2, v on 1 and 3: from corner 0, 1, 3, 0 to 1, 2, 2, 3).
const int EDGE_ROW[16] = int[16](0, 1, 2, 3, 3, 7, 11, 15, 12, 13, 14, 15, 0, 4, 8, 12);
const int INNER_ROW[16] = int[16](4, 5, 6, 7, 2, 6, 10, 14, 8, 9, 10, 11, 1, 5, 9, 13);
const int START[4] = int[4](0, 1, 3, 0);
const int END[4] = int[4](1, 2, 2, 3);

/// Edge k of patch pi at x: the cubic in the canonical frame and the normal
/// cross(dC/dt, sum B_i (l_i - r_i)), l the row on the left of the canonical direction.
void acc_edge(uint pi, int k, float x, out vec3 pos, out vec3 nrm) {
    uvec4 c = acc[pi].corners;
    bool forward = c[START[k]] < c[END[k]];
    // x runs counter-clockwise (corner k to k + 1) on edges 0 and 1; the patch lies left of
    // its counter-clockwise direction; nbr rows are stored counter-clockwise.
    bool ccw = k < 2;
    bool own_left = forward == ccw;
    float t, s;
    edge_ts(x, forward, t, s);
    precise vec3 e[4];
    precise vec3 d[4];
    for (int i = 0; i < 4; ++i) {
        int o = forward ? i : 3 - i;
        vec3 own = acc[pi].b[INNER_ROW[4 * k + o]].xyz;
        vec3 other = acc[pi].nbr[4 * k + (ccw ? o : 3 - o)].xyz;
        e[i] = acc[pi].b[EDGE_ROW[4 * k + o]].xyz;
        d[i] = own_left ? own - other : other - own;
    }
    vec4 bt, dbt;
    bernstein3(t, s, bt, dbt);
    precise vec3 p = ((bt.x * e[0] + bt.y * e[1]) + bt.z * e[2]) + bt.w * e[3];
    precise vec3 tangent = ((dbt.x * e[0] + dbt.y * e[1]) + dbt.z * e[2]) + dbt.w * e[3];
    precise vec3 cross_dir = ((bt.x * d[0] + bt.y * d[1]) + bt.z * d[2]) + bt.w * d[3];
    precise vec3 nn = normalize(cross(tangent, cross_dir));
    pos = p;
    nrm = nn;
}

void main() {
    float u = gl_TessCoord.x;
    float v = gl_TessCoord.y;
    uint pi = chunk.patch_base + uint(gl_PrimitiveID);
    vec3 cp[16];
    for (int k = 0; k < 16; ++k) {
        cp[k] = acc[pi].b[k].xyz;
    }
    vec3 p;
    vec3 nrm;
    bezier_surface(cp, u, v, p, nrm);
    bool u_edge = (u == 0.0 || u == 1.0);
    bool v_edge = (v == 0.0 || v == 1.0);
    if (u_edge && v_edge) {
        // The shared limit position and normal of the corner vertex (as every scheme).
        p = acc[pi].b[int(3.0 * u + 12.0 * v)].xyz;
        quad_corner_point(acc[pi].corners, u, v, p, nrm);
    } else if (v_edge) {
        acc_edge(pi, v == 0.0 ? 0 : 2, u, p, nrm);
    } else if (u_edge) {
        acc_edge(pi, u == 1.0 ? 1 : 3, v, p, nrm);
    }
    displace_point(acc[pi].face, NO_SUB_FACE, vec2(u, v), p, nrm);
    t_world = p;
    t_normal = nrm;
    t_class = acc[pi].cls;
    gl_Position = frame.view_proj * vec4(p, 1.0);
#ifdef CAPTURE
    capture_point(acc[pi].face, vec2(u, v), p, nrm);
#endif
}
