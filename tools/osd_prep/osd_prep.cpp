// osd_prep: OpenSubdiv 3.5's preprocessing of `--scheme adaptive`'s work, REPEAT times, for
// instruction counts under valgrind beside tessera's `examples/adaptive_preprocess` (docs/measured.md,
// "CPU preprocessing"): per repeat a `Far::TopologyRefiner` from the OBJ (loaded and tagged as
// tools/osd_eval/osd_eval.cpp does, `tools/osd_eval/obj_mesh.h`), `RefineAdaptive` to ISOLATION and, unless STEP says
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

#include "../osd_eval/obj_mesh.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace OpenSubdiv;

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

    const Far::TopologyDescriptor desc = describe(m);
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
