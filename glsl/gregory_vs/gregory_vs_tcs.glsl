// Two-stage Gregory construction, stage 2 (§4.2): the TCS body of gregory_vs_{quad,tri}.tesc.
// The patch primitive is the face's NC (4 or 3) vertices with their per-vertex data from
// gregory_vs.vert; invocation k writes control point k (order of gregory/gregory.glsl): corner
// points and edge points are picked from the per-vertex data with the patch's ring offsets
// (Fig. 8), face points are built with eq. 6. Per-vertex data is relative to the vertex's control
// position, which is the origin of its corner's points (corner frames, gregory/gregory.glsl);
// a face point mixing two corners moves the other corner's edge point into its own frame.
// Define NC (corners) and D_OWN (eq. 6's d: 3 for quads, 4 for triangles) first.
#ifndef TESSERA_GREGORY_VS_TCS_GLSL
#define TESSERA_GREGORY_VS_TCS_GLSL

#include "frame.glsl"
#include "tess_factors.glsl"
#include "gregory/gregory.glsl"
#include "gregory_vs.glsl"

layout(vertices = 5 * NC) out;

layout(location = 0) in vec4 v_data[][GVS_SLOTS];
layout(location = 0) out vec3 g_cp[];
layout(location = 1) patch out vec3 g_eout[2 * NC];
layout(location = 1 + 2 * NC) patch out vec3 g_nbr[2 * NC];

float get(int corner, int f) {
    return v_data[corner][1 + f / 4][f % 4];
}

vec3 get3(int corner, int f) {
    return vec3(get(corner, f), get(corner, f + 1), get(corner, f + 2));
}

uint corner_vertex(int corner) {
    return gpatches[chunk.patch_base + uint(gl_PrimitiveID)].corners[corner];
}

/// Origin of corner `corner`'s per-vertex data (gregory_vs.vert: relative to the vertex's own
/// control position).
vec3 corner_origin(int corner) {
    return control_point(corner_vertex(corner));
}

/// Point x of corner `from`'s frame in corner `to`'s frame, with the same bits in every patch
/// that moves it between the same two vertices.
vec3 in_frame(vec3 x, int from, int to) {
    precise vec3 shift = corner_origin(from) - corner_origin(to);
    precise vec3 y = x + shift;
    return y;
}

bool smooth_corner(int corner) {
    return conn[4u * corner_vertex(corner) + 3u] == GVS_KIND_SMOOTH;
}

/// Number of ring edges of the corner's vertex.
int edge_count(int corner) {
    return int(conn[4u * corner_vertex(corner) + 1u]);
}

/// Edge point of corner `corner`'s vertex on its ring edge j (mod the edge count).
vec3 edge_pt(int corner, int j) {
    int ne = edge_count(corner);
    int jj = (j + ne) % ne;
    return get3(corner, smooth_corner(corner) ? 6 * jj : 9 * jj);
}

/// Transversal vector of face j (of the corner's ring) across its edge j, into face j.
vec3 r_plus(int corner, int j) {
    int ne = edge_count(corner);
    int jj = (j + ne) % ne;
    return get3(corner, smooth_corner(corner) ? 6 * jj + 3 : 9 * jj + 3);
}

/// Transversal vector of face j across its edge j + 1, into face j (smooth: -r_{j+1}).
vec3 r_minus(int corner, int j) {
    int ne = edge_count(corner);
    int jj = (j + ne) % ne;
    if (smooth_corner(corner)) {
        return -get3(corner, 6 * ((jj + 1) % ne) + 3);
    }
    return get3(corner, 9 * jj + 6);
}

/// cos of condition (1) for face j of the corner's ring.
float face_cos(int corner, int j) {
    int nf = int(abs(v_data[corner][0].w));
    return gvs_face_cosine(corner_vertex(corner), (j + nf) % nf);
}

/// Which edges of face j at the corner are sharp when its face points beside them are
/// one-sided (patch::gregory::GregoryVertex::one_sided; the vertex stage's sign of slot 0's w):
/// bit 0 edge j, bit 1 edge j + 1; 0 otherwise.
int one_sided(int corner, int j) {
    if (v_data[corner][0].w > 0.0) {
        return 0;
    }
    uint v = corner_vertex(corner);
    int ne = edge_count(corner);
    int nf = int(abs(v_data[corner][0].w));
    int jj = (j + nf) % nf;
    uint w = conn[conn[4u * v] + uint(ne + jj)];
    int s = int(w & 0xffffu);
    int k = int(w >> 16);
    return (jj == s ? 1 : 0) | ((jj + 1) % ne == (s + k) % ne ? 2 : 0);
}

/// Face point next to the edge from corner a to corner b of a face with `d` = 3 (quad) or 4
/// (triangle) (eq. 6 as re-derived in src/patch/gregory/vertex.rs `face_point`):
/// (c_b p_a + (d - 2 c_a - c_b) e_ab + 2 c_a e_ba + r) / d, c = cos of condition (1) of the face's
/// sector at each end. `precise`: the neighbour patch recomputes it bitwise (g_nbr).
vec3 face_point(float d, float ca, float cb, vec3 pa, vec3 e_ab, vec3 e_ba, vec3 r) {
    precise vec3 f = (cb * pa + (d - 2.0 * ca - cb) * e_ab + 2.0 * ca * e_ba + r) / d;
    return f;
}

void main() {
    uint patch_index = chunk.patch_base + uint(gl_PrimitiveID);
    int id = gl_InvocationID;
    int kind = id / NC;
    int i = id % NC;
    int nx = (i + 1) % NC;
    int pr = (i + NC - 1) % NC;
    int j = int(corner_ring[4u * patch_index + uint(i)]);
    int j_nx = int(corner_ring[4u * patch_index + uint(nx)]);
    int j_pr = int(corner_ring[4u * patch_index + uint(pr)]);
    vec3 x;
    if (kind == 0) {
        x = v_data[i][0].xyz;
    } else if (kind == 1) {
        x = edge_pt(i, j);
    } else if (kind == 2) {
        x = edge_pt(i, j + 1);
    } else {
        // One-sided face points (patch::gregory::eval `assemble`): beside one sharp edge the
        // corner's other face point; a corner alone in its corner sector takes the far cosine 0.
        int sides = one_sided(i, j);
        bool alone = sides == 3 && conn[4u * corner_vertex(i) + 3u] == GVS_KIND_CORNER;
        bool plus = kind == 3 ? sides != 1 : sides == 2;
        if (plus) {
            x = face_point(D_OWN, face_cos(i, j), alone ? 0.0 : face_cos(nx, j_nx),
                           v_data[i][0].xyz, edge_pt(i, j),
                           in_frame(edge_pt(nx, j_nx + 1), nx, i), r_plus(i, j));
        } else {
            x = face_point(D_OWN, face_cos(i, j), alone ? 0.0 : face_cos(pr, j_pr),
                           v_data[i][0].xyz, edge_pt(i, j + 1),
                           in_frame(edge_pt(pr, j_pr), pr, i), r_minus(i, j));
        }
    }
    g_cp[gl_InvocationID] = x;
    if (id < 2 * NC) {
        // Neighbour across edge k = id / 2 (corner k -> k1; its face is jk - 1 in corner k's
        // ring and jk1 + 1 in corner k1's): its other edge point and its face point next to the
        // edge, at corner k (even id) or k1 (odd id), computed as the neighbour computes them.
        // Unused (any value) where the edge is sharp or on a boundary (flags bit 12 + k).
        int k = id / 2;
        int k1 = (k + 1) % NC;
        int jk = int(corner_ring[4u * patch_index + uint(k)]);
        int jk1 = int(corner_ring[4u * patch_index + uint(k1)]);
        uint nflags = gpatches[patch_index].flags;
        float d_nbr = ((nflags & (1u << uint(8 + k))) != 0u) ? 4.0 : 3.0;
        vec3 e_ab = edge_pt(k, jk);
        vec3 e_ba = edge_pt(k1, jk1 + 1);
        float ca = face_cos(k, jk - 1);
        float cb = face_cos(k1, jk1 + 1);
        if ((id & 1) == 0) {
            g_eout[id] = edge_pt(k, jk - 1);
            g_nbr[id] = face_point(d_nbr, ca, cb, v_data[k][0].xyz, e_ab, in_frame(e_ba, k1, k),
                                   r_minus(k, jk - 1));
        } else {
            g_eout[id] = edge_pt(k1, jk1 + 2);
            g_nbr[id] = face_point(d_nbr, cb, ca, v_data[k1][0].xyz, e_ba, in_frame(e_ab, k, k1),
                                   r_plus(k1, jk1 + 1));
        }
    }
    if (id == 0) {
        uvec4 c = gpatches[patch_index].corners;
#if NC == 3
        set_gregory_tri_tess_levels(c);
#else
        set_quad_tess_levels(c);
#endif
    }
    CULL_PATCH_AT(g_cp, 5 * NC, corner_origin(cull_k % NC));
}

#endif
