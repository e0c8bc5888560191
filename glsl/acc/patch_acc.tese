#version 450
// ACC patch (acc.glsl): the bicubic geometry patch inside with the normal of its tangent
// patches; corners and edges by the shared watertight rules. Drawn whole. Defines: SPACING, CAPTURE.
#include "frame.glsl"
#include "watertight.glsl"
#include "acc.glsl"
#include "displace.glsl"
#ifdef CAPTURE
#include "capture.glsl"
#endif
#include "tes_outputs.glsl"

layout(quads, SPACING, cw) in;

/// Per edge k, its Bézier row in the direction of the edge's coordinate x (u on edges 0 and 2, v
/// on 1 and 3: from corner 0, 1, 3, 0 to 1, 2, 2, 3).
const int EDGE_ROW[16] = int[16](0, 1, 2, 3, 3, 7, 11, 15, 12, 13, 14, 15, 0, 4, 8, 12);
const int START[4] = int[4](0, 1, 3, 0);
const int END[4] = int[4](1, 2, 2, 3);

/// Edge k of patch pi at x: the cubic in the canonical frame and the normal of the edge's frame,
/// normalize(D(t) x X(t)), which both faces hold.
void acc_edge(uint pi, int k, float x, out vec3 pos, out vec3 nrm) {
    uvec4 c = acc[pi].corners;
    bool forward = c[START[k]] < c[END[k]];
    float t, s;
    edge_ts(x, forward, t, s);
    precise vec3 e[4];
    for (int i = 0; i < 4; ++i) {
        e[i] = acc[pi].b[EDGE_ROW[4 * k + (forward ? i : 3 - i)]].xyz;
    }
    vec4 bt, dbt;
    bernstein3(t, s, bt, dbt);
    precise vec3 p = ((bt.x * e[0] + bt.y * e[1]) + bt.z * e[2]) + bt.w * e[3];
    int f = 7 * k;
    precise vec3 versal = ((s * s) * acc[pi].edge[f].xyz + (2.0 * s * t) * acc[pi].edge[f + 1].xyz)
                        + (t * t) * acc[pi].edge[f + 2].xyz;
    precise vec3 cross_dir = ((bt.x * acc[pi].edge[f + 3].xyz + bt.y * acc[pi].edge[f + 4].xyz)
                              + bt.z * acc[pi].edge[f + 5].xyz)
                           + bt.w * acc[pi].edge[f + 6].xyz;
    precise vec3 nn = normalize(cross(versal, cross_dir));
    pos = p;
    nrm = nn;
}

/// The shading normal U x V of the tangent patches at (u, v).
vec3 tangent_normal(uint pi, float u, float v) {
    float su = 1.0 - u;
    float sv = 1.0 - v;
    vec3 bu2 = vec3(su * su, 2.0 * su * u, u * u);
    vec3 bv2 = vec3(sv * sv, 2.0 * sv * v, v * v);
    vec4 bu3, dbu, bv3, dbv;
    bernstein3(u, su, bu3, dbu);
    bernstein3(v, sv, bv3, dbv);
    vec3 tu = vec3(0.0);
    vec3 tv = vec3(0.0);
    for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 3; ++i) {
            tu += (bu2[i] * bv3[j]) * acc[pi].tu[3 * j + i].xyz;
        }
    }
    for (int j = 0; j < 3; ++j) {
        for (int i = 0; i < 4; ++i) {
            tv += (bu3[i] * bv2[j]) * acc[pi].tv[4 * j + i].xyz;
        }
    }
    vec3 n = cross(tu, tv);
    float len = length(n);
    return len > 0.0 ? n / len : vec3(0.0, 0.0, 1.0);
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
    vec3 du, dv;
    bezier_surface_frame(cp, u, v, p, nrm, du, dv);
    nrm = tangent_normal(pi, u, v);
    bool u_edge = (u == 0.0 || u == 1.0);
    bool v_edge = (v == 0.0 || v == 1.0);
    if (u_edge && v_edge) {
        // The shared limit position and normal of the corner vertex (as every scheme).
        p = acc[pi].b[int(3.0 * u + 12.0 * v)].xyz;
        quad_corner_point(acc[pi].corners, acc[pi].face, u, v, p, nrm);
    } else if (v_edge) {
        acc_edge(pi, v == 0.0 ? 0 : 2, u, p, nrm);
    } else if (u_edge) {
        acc_edge(pi, u == 1.0 ? 1 : 3, v, p, nrm);
    }
    displace_point(acc[pi].face, NO_SUB_FACE, vec2(u, v), uv_tangents(du, dv), p, nrm);
    t_world = p;
    t_normal = nrm;
    t_class = acc[pi].cls;
    gl_Position = frame.view_proj * vec4(p, 1.0);
#ifdef CAPTURE
    capture_point(acc[pi].face, vec2(u, v), p, nrm);
#endif
}
