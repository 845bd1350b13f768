// yade-mss public API: the table of contents. These headers, and only these, are installed (include/mss/);
// the implementation lives in pkg/mss/ subfolders by layer: core/ (geometry: grids, meshes, distances, the
// distance transform, mass properties), generation/ (the pipeline, the option table, scoring, and engine/),
// io/ (readers and writers, one file a format, and the table of formats), platform/ (threads, memory),
// spheropolygon/.
#pragma once

#include "mss/compare.hpp"       // comparing any generator's spheres with a grain
#include "mss/generate.hpp"      // the generator (sections 3.3-3.5)
#include "mss/grid.hpp"          // voxel grids: world and voxel coordinates
#include "mss/io.hpp"            // files: the format table, readers and writers
#include "mss/mass.hpp"          // mass properties of meshes, voxels, sphere unions
#include "mss/mesh.hpp"          // triangle meshes: checks, defects
#include "mss/options.hpp"       // the option table every front end is made from
#include "mss/planes.hpp"        // planes no sphere crosses: fragments, walls
#include "mss/score.hpp"         // scoring sphere sets (eq. 7, 27)
#include "mss/spheres.hpp"       // sphere sets
#include "mss/spheropolygon.hpp" // 2-D: spheropolygons from particle images (the second paper)
#include "mss/surface.hpp"       // the surface of a clump: its spheres' union as a mesh
#include "mss/version.hpp"       // this library's version
#include "mss/voxelize.hpp"      // voxelisation (section 2.2) and grid resolution
#include "mss/work.hpp"          // heavy requests: work estimates, progress, stopping
