// yade-mss public API: the table of contents.
#pragma once

#include "mss/clip.hpp"          // distances to meshes, winding numbers, constraint planes
#include "mss/compare.hpp"       // comparing any generator's spheres with a grain: frames, one table row
#include "mss/edt.hpp"           // exact Euclidean distance transform (eq. 8)
#include "mss/generate.hpp"      // the generator (sections 3.3-3.5)
#include "mss/grid.hpp"          // voxel grids
#include "mss/mass.hpp"          // mass properties of meshes, voxels, sphere unions
#include "mss/maxima.hpp"        // local maxima and sub-voxel refinement (eq. 11-24)
#include "mss/mesh.hpp"          // triangle meshes and their files
#include "mss/npy.hpp"           // .npy voxel volumes
#include "mss/options.hpp"       // the option table every front end is made from
#include "mss/score.hpp"         // scoring sphere sets (eq. 7, 27)
#include "mss/spheres.hpp"       // sphere sets and their files
#include "mss/spheropolygon.hpp" // 2-D: spheropolygons from particle images (the second paper)
#include "mss/voxelize.hpp"      // voxelisation (section 2.2)
