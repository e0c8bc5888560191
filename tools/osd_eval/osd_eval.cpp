// osd_eval: OpenSubdiv 3.5 Far feature-adaptive patches with Gregory-basis end caps, evaluated on the
// same (face, u, v) grid as `tessera limit --grid N`, in the same line format, so the two can be
// compared point by point (tools/osd_eval/compare.py). A dev-only yardstick, never part of the crate:
//   g++ -O2 -std=c++14 osd_eval.cpp -o osd_eval -losdCPU      (Debian: libosd-dev)
//   osd_eval MESH.obj ISOLATION GRID [single-crease] > osd.txt
//   osd_eval MESH.obj ISOLATION - [single-crease] < points.txt > osd.txt   (the points of the
//   first three columns of each input line, e.g. what examples/adaptive_grid.rs writes)
//   osd_eval MESH.obj 0 0 points > points.txt   (the 20 Gregory-basis points of every quad drawn
//     as a Gregory-basis patch: `f corner P|Ep|Em|Fp|Fm x y z`, corner i = face vertex i, Ep
//     towards corner i + 1, Fp next to the edge i -> i + 1, as tessera's e_plus / f_plus)
//   osd_eval MESH.obj ISOLATION - patch-points < points.txt   (the control points of the patch
//     holding each input point, at any isolation: an end cap's 20 Gregory-basis points as above,
//     after a `# f:k u v type T depth D` line; compare with examples/endcap_points.rs)
// Reads `v`, `f` and the OpenSubdiv tags tessera reads (crease, corner, hole, interpolateboundary,
// creasemethod; interpolateboundary 0 none, 1 edge-and-corner (the default), 2 edge-only, as tessera).
// Quads print `f u v ...`; sub-face k of another face prints `f:k u v ...` (ptex order).
#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/ptexIndices.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include "obj_mesh.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace OpenSubdiv;

int main(int argc, char **argv) {
    if (argc < 4) {
        std::fprintf(stderr, "usage: osd_eval MESH.obj ISOLATION GRID|- [single-crease|points|patch-points]\n");
        return 2;
    }
    Mesh m;
    if (!load(argv[1], m)) {
        std::fprintf(stderr, "cannot read %s\n", argv[1]);
        return 1;
    }
    const int isolation = std::atoi(argv[2]), grid = std::atoi(argv[3]);
    const bool singleCrease = argc > 4 && std::string(argv[4]) == "single-crease";
    const bool printPoints = argc > 4 && std::string(argv[4]) == "points";
    const bool patchPoints = argc > 4 && std::string(argv[4]) == "patch-points";

    const Far::TopologyDescriptor desc = describe(m);
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    Far::TopologyRefiner *refiner =
        Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, m.options));
    if (!refiner) return 1;

    Far::PatchTableFactory::Options popts(isolation);
    popts.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
    popts.SetPatchPrecision<double>();
    popts.useSingleCreasePatch = singleCrease;
    popts.useInfSharpPatch = true;
    Far::TopologyRefiner::AdaptiveOptions aopts = popts.GetRefineAdaptiveOptions();
    refiner->RefineAdaptive(aopts);
    Far::PatchTable *table = Far::PatchTableFactory::Create(*refiner, popts);

    const int refined = refiner->GetNumVerticesTotal();
    std::vector<Point> points(refined + table->GetNumLocalPoints());
    std::copy(m.verts.begin(), m.verts.end(), points.begin());
    Far::PrimvarRefinerReal<double> primvar(*refiner);
    Point *src = points.data();
    for (int level = 1; level <= refiner->GetMaxLevel(); ++level) {
        Point *dst = src + refiner->GetLevel(level - 1).GetNumVertices();
        primvar.Interpolate(level, src, dst);
        src = dst;
    }
    // End-cap points from the local point stencils (double, as the patch precision).
    if (Far::StencilTableReal<double> const *local = table->GetLocalPointStencilTable<double>()) {
        for (int r = 0; r < local->GetNumStencils(); ++r) {
            Far::StencilReal<double> st = local->GetStencil(r);
            Point &out = points[refined + r];
            out.Clear();
            for (int c = 0; c < st.GetSize(); ++c) out.AddWithWeight(points[st.GetVertexIndices()[c]], st.GetWeights()[c]);
        }
    }

    Far::PatchMap map(*table);
    Far::PtexIndices ptex(*refiner);
    std::fprintf(stderr, "patches %d, local points %d\n", table->GetNumPatchesTotal(), table->GetNumLocalPoints());
    if (table->GetNumPatchesTotal() == 0)
        // OpenSubdiv draws no patch at level 0 of a mesh with a non-quad face (its faces are
        // isolated from level 1 on): e.g. gregory_test2 and gregory_test8 at isolation 0.
        std::fprintf(stderr, "no patches: a mesh with non-quad faces needs isolation >= 1\n");
    const Far::TopologyLevel &base = refiner->GetLevel(0);
    std::vector<double> w(20), wu(20), wv(20);
    if (printPoints) {
        static const char *names[5] = {"P", "Ep", "Em", "Fp", "Fm"};
        for (int f = 0; f < base.GetNumFaces(); ++f) {
            if (base.IsFaceHole(f) || base.GetFaceVertices(f).size() != 4) continue;
            Far::PatchTable::PatchHandle const *h = map.FindPatch(ptex.GetFaceId(f), 0.5, 0.5);
            if (!h || table->GetPatchDescriptor(*h).GetType() != Far::PatchDescriptor::GREGORY_BASIS) continue;
            if (table->GetPatchParam(*h).GetDepth() != 0) continue;
            Far::ConstIndexArray cvs = table->GetPatchVertices(*h);
            for (int c = 0; c < 20; ++c) {
                Point const &q = points[cvs[c]];
                std::printf("%d %d %s %.17g %.17g %.17g\n", f, c / 5, names[c % 5], q.p[0], q.p[1], q.p[2]);
            }
        }
        delete table;
        delete refiner;
        return 0;
    }
    // Sub-face k of base face f (k = 0 for quads) at (u, v): one output line, or none where no
    // patch covers the point (holes).
    auto eval = [&](int f, int k, double u, double v) {
        const bool quad = base.GetFaceVertices(f).size() == 4;
        Far::PatchTable::PatchHandle const *h = map.FindPatch(ptex.GetFaceId(f) + k, u, v);
        if (!h) return;
        table->EvaluateBasis(*h, u, v, w.data(), wu.data(), wv.data());
        Far::ConstIndexArray cvs = table->GetPatchVertices(*h);
        Point p, du, dv;
        p.Clear(), du.Clear(), dv.Clear();
        for (int c = 0; c < cvs.size(); ++c) {
            p.AddWithWeight(points[cvs[c]], w[c]);
            du.AddWithWeight(points[cvs[c]], wu[c]);
            dv.AddWithWeight(points[cvs[c]], wv[c]);
        }
        double nn[3] = {du.p[1] * dv.p[2] - du.p[2] * dv.p[1], du.p[2] * dv.p[0] - du.p[0] * dv.p[2],
                        du.p[0] * dv.p[1] - du.p[1] * dv.p[0]};
        const double len = std::sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
        for (double &x : nn) x = len > 0 ? x / len : 0.0;
        if (quad)
            std::printf("%d", f);
        else
            std::printf("%d:%d", f, k);
        std::printf(" %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", u, v, p.p[0], p.p[1], p.p[2], nn[0],
                    nn[1], nn[2]);
    };
    // The control points of the patch holding sub-face k of base face f at (u, v): a `# f u v
    // type T depth D` line (T a Far::PatchDescriptor::Type), then one `corner P|Ep|Em|Fp|Fm x y z`
    // line per Gregory-basis point (`index x y z` for other patch types).
    auto printPatch = [&](int f, int k, double u, double v) {
        Far::PatchTable::PatchHandle const *h = map.FindPatch(ptex.GetFaceId(f) + k, u, v);
        if (!h) return;
        const Far::PatchDescriptor::Type type = table->GetPatchDescriptor(*h).GetType();
        std::printf("# %d:%d %.17g %.17g type %d depth %d\n", f, k, u, v, int(type),
                    table->GetPatchParam(*h).GetDepth());
        static const char *names[5] = {"P", "Ep", "Em", "Fp", "Fm"};
        Far::ConstIndexArray cvs = table->GetPatchVertices(*h);
        for (int c = 0; c < cvs.size(); ++c) {
            Point const &q = points[cvs[c]];
            if (type == Far::PatchDescriptor::GREGORY_BASIS)
                std::printf("%d %s", c / 5, names[c % 5]);
            else
                std::printf("%d", c);
            std::printf(" %.17g %.17g %.17g\n", q.p[0], q.p[1], q.p[2]);
        }
    };
    if (std::string(argv[3]) == "-") {
        // Points from standard input: the first three columns of `f u v ...` / `f:k u v ...` lines.
        char face[64];
        double u, v;
        char rest[4096];
        while (std::fgets(rest, sizeof rest, stdin)) {
            if (std::sscanf(rest, "%63s %lf %lf", face, &u, &v) != 3) continue;
            int f = 0, k = 0;
            if (std::sscanf(face, "%d:%d", &f, &k) < 1 || f < 0 || f >= base.GetNumFaces()) continue;
            if (base.IsFaceHole(f)) continue;
            if (patchPoints)
                printPatch(f, k, u, v);
            else
                eval(f, k, u, v);
        }
    } else {
        for (int f = 0; f < base.GetNumFaces(); ++f) {
            if (base.IsFaceHole(f)) continue;
            const int n = base.GetFaceVertices(f).size();
            for (int k = 0; k < (n == 4 ? 1 : n); ++k)
                for (int j = 0; j <= grid; ++j)
                    for (int i = 0; i <= grid; ++i) eval(f, k, double(i) / grid, double(j) / grid);
        }
    }
    delete table;
    delete refiner;
    return 0;
}
