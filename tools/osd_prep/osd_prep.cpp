// osd_prep: OpenSubdiv 3.5's preprocessing of `--scheme adaptive`'s work, REPEAT times, for
// instruction counts under valgrind beside tessera's `examples/adaptive_preprocess` (README,
// "CPU preprocessing"): per repeat a `Far::TopologyRefiner` from the OBJ (loaded and tagged as
// tools/osd_eval/osd_eval.cpp does), `RefineAdaptive` to ISOLATION and, unless STEP says
// otherwise, `PatchTableFactory::Create` with Gregory-basis end caps (double precision, infinitely
// sharp patches, single-crease patches unless `no-single-crease`). A dev-only yardstick, never part
// of the crate:
//   g++ -O2 -std=c++14 osd_prep.cpp -o osd_prep -losdCPU      (Debian: libosd-dev)
//   osd_prep MESH.obj ISOLATION REPEAT [create|refine|patches|stencils] [no-single-crease]
// STEP (default `patches`): `create` builds the refiner only, `refine` adds RefineAdaptive,
// `patches` adds the patch table, `stencils` adds the refined vertices' stencil table (the
// counterpart of tessera's kernels' tables, which OpenSubdiv's own figure leaves out).
// Instructions per step: (count at REPEAT 3 - count at REPEAT 1) / 2, and the difference of two
// steps (tools/osd_prep/README.md).
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace OpenSubdiv;

struct Point {
    double p[3];
    void Clear() { p[0] = p[1] = p[2] = 0.0; }
    void AddWithWeight(Point const &s, double w) {
        for (int k = 0; k < 3; ++k) p[k] += w * s.p[k];
    }
};

struct Mesh {
    std::vector<Point> verts;
    std::vector<int> sizes, indices, creasePairs, cornerVerts, holes;
    std::vector<float> creaseWeights, cornerWeights;
    Sdc::Options options;
};

static int index_of(const std::string &token) { return std::stoi(token.substr(0, token.find('/'))) - 1; }

static bool load(const char *path, Mesh &m) {
    std::ifstream in(path);
    if (!in) return false;
    m.options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream s(line);
        std::string tag;
        s >> tag;
        if (tag == "v") {
            Point p;
            s >> p.p[0] >> p.p[1] >> p.p[2];
            m.verts.push_back(p);
        } else if (tag == "f") {
            std::string t;
            int n = 0;
            while (s >> t) {
                m.indices.push_back(index_of(t));
                ++n;
            }
            m.sizes.push_back(n);
        } else if (tag == "t") {
            std::string name, counts;
            s >> name >> counts;
            int ni = 0, nf = 0, ns = 0;
            std::sscanf(counts.c_str(), "%d/%d/%d", &ni, &nf, &ns);
            std::vector<int> ints(ni);
            for (auto &i : ints) s >> i;
            std::vector<float> floats(nf);
            for (auto &f : floats) s >> f;
            if (name == "crease")
                for (int k = 0; k + 1 < ni; k += 2) {
                    m.creasePairs.push_back(ints[k]);
                    m.creasePairs.push_back(ints[k + 1]);
                    m.creaseWeights.push_back(floats.empty() ? 10.0f : floats[0]);
                }
            else if (name == "corner")
                for (int k = 0; k < ni; ++k) {
                    m.cornerVerts.push_back(ints[k]);
                    m.cornerWeights.push_back(floats.empty() ? 10.0f : floats[0]);
                }
            else if (name == "hole")
                for (int k = 0; k < ni; ++k) m.holes.push_back(ints[k]);
            else if (name == "interpolateboundary" && ni > 0)
                m.options.SetVtxBoundaryInterpolation(
                    ints[0] == 0 ? Sdc::Options::VTX_BOUNDARY_NONE
                    : ints[0] == 1 ? Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER
                                   : Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
            else if (name == "creasemethod") {
                std::string method;
                s >> method;
                if (method == "chaikin") m.options.SetCreasingMethod(Sdc::Options::CREASE_CHAIKIN);
            }
        }
    }
    return true;
}

int main(int argc, char **argv) {
    if (argc < 4) {
        std::fprintf(stderr,
                     "usage: osd_prep MESH.obj ISOLATION REPEAT [create|refine|patches|stencils] "
                     "[no-single-crease]\n");
        return 2;
    }
    Mesh m;
    if (!load(argv[1], m)) {
        std::fprintf(stderr, "cannot read %s\n", argv[1]);
        return 1;
    }
    const int isolation = std::atoi(argv[2]), repeat = std::atoi(argv[3]);
    const std::string step = argc > 4 ? argv[4] : "patches";
    const bool singleCrease = !(argc > 5 && std::string(argv[5]) == "no-single-crease");
    const int depth = step == "create" ? 0 : step == "refine" ? 1 : step == "patches" ? 2 : 3;

    Far::TopologyDescriptor desc;
    desc.numVertices = (int)m.verts.size();
    desc.numFaces = (int)m.sizes.size();
    desc.numVertsPerFace = m.sizes.data();
    desc.vertIndicesPerFace = m.indices.data();
    desc.numCreases = (int)m.creaseWeights.size();
    desc.creaseVertexIndexPairs = m.creasePairs.data();
    desc.creaseWeights = m.creaseWeights.data();
    desc.numCorners = (int)m.cornerWeights.size();
    desc.cornerVertexIndices = m.cornerVerts.data();
    desc.cornerWeights = m.cornerWeights.data();
    desc.numHoles = (int)m.holes.size();
    desc.holeIndices = m.holes.data();
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;

    Far::PatchTableFactory::Options popts(isolation);
    popts.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
    popts.SetPatchPrecision<double>();
    popts.useSingleCreasePatch = singleCrease;
    popts.useInfSharpPatch = true;
    const Far::TopologyRefiner::AdaptiveOptions aopts = popts.GetRefineAdaptiveOptions();

    long patches = 0, stencils = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < repeat; ++r) {
        Far::TopologyRefiner *refiner =
            Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, m.options));
        if (!refiner) return 1;
        if (depth >= 1) refiner->RefineAdaptive(aopts);
        if (depth >= 2) {
            Far::PatchTable *table = Far::PatchTableFactory::Create(*refiner, popts);
            patches = table->GetNumPatchesTotal();
            delete table;
        }
        if (depth >= 3) {
            Far::StencilTableFactory::Options sopts;
            sopts.generateOffsets = true;
            sopts.generateIntermediateLevels = true;
            Far::StencilTable const *st = Far::StencilTableFactory::Create(*refiner, sopts);
            stencils = st->GetNumStencils();
            delete st;
        }
        delete refiner;
    }
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%s x %d: %.3f ms each (%ld patches, %ld stencils)\n", step.c_str(), repeat,
                ms / repeat, patches, stencils);
    return 0;
}
