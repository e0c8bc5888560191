// The OBJ reading shared by the dev-only OpenSubdiv tools (osd_eval.cpp, ../osd_prep/osd_prep.cpp):
// `v`, `f` and the OpenSubdiv tags tessera reads (crease, corner, hole, interpolateboundary,
// creasemethod; interpolateboundary 0 none, 1 edge-and-corner (the default), 2 edge-only, as tessera).
#pragma once

#include <opensubdiv/far/topologyDescriptor.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

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
    OpenSubdiv::Sdc::Options options;
};

static int index_of(const std::string &token) { return std::stoi(token.substr(0, token.find('/'))) - 1; }

static bool load(const char *path, Mesh &m) {
    std::ifstream in(path);
    if (!in) return false;
    m.options.SetVtxBoundaryInterpolation(OpenSubdiv::Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
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
                    ints[0] == 0 ? OpenSubdiv::Sdc::Options::VTX_BOUNDARY_NONE
                    : ints[0] == 1 ? OpenSubdiv::Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER
                                   : OpenSubdiv::Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
            else if (name == "creasemethod") {
                std::string method;
                s >> method;
                if (method == "chaikin") m.options.SetCreasingMethod(OpenSubdiv::Sdc::Options::CREASE_CHAIKIN);
            }
        }
    }
    return true;
}

// The refiner's description of `m` (pointing into `m`).
static OpenSubdiv::Far::TopologyDescriptor describe(const Mesh &m) {
    OpenSubdiv::Far::TopologyDescriptor desc;
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
    return desc;
}
