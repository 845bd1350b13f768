#include "mss/options.hpp"

#include <limits>

// The option table: one row an option, the single source from which the command line, the bindings and the
// docstrings are made (CONVENTIONS.md: one option table, many front ends).

namespace mss {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kIntMax = 2147483647.0;
constexpr double kInt64Max = 9223372036854775807.0;
/// The largest memoryLimit (GiB): 1 PiB, far above any machine, far below a size_t's overflow.
constexpr double kMaxMemoryGiB = 1048576.0;

using T = OptionType;
namespace c = command;
constexpr unsigned kGrain = c::Generate | c::Compare | c::Info | c::Batch | c::Preview | c::Curve |
                            c::Ochart | c::Export | c::Triaxial;
constexpr unsigned kGenerating = c::Generate | c::Batch | c::Export; // the commands whose work is generation
constexpr unsigned kGen = kGenerating | c::Triaxial;                 // a generation's own options

// name, flag, python, type, default, low, high, lowOpen, highOpen, choices, unit, metavar, help, commands
const std::vector<OptionSpec> kTable = {
    // what is written
    {"output", "-o,--output", false, T::Text, "", 0, 0, false, false, "", "", "OUT",
     "the sphere file: .csv (x,y,z,r), .txt (YADE's text clump: x y z r clumpId) or .vtk; or a template with "
     "the grain's mass properties (as mss export): .clu (Kratos) or .p3dat (PFC)",
     c::Generate},
    {"output", "-o,--output", false, T::Text, "", 0, 0, false, false, "", "", "DIR",
     "the output folder (a rerun resumes in it)", c::Batch},
    {"output", "-o,--output", false, T::Text, "", 0, 0, false, false, "", "", "PNG", "the picture to write",
     c::Preview},
    {"output", "-o,--output", false, T::Text, "", 0, 0, false, false, "", "", "PNG",
     "the chart to write; its CSV is written beside it", c::Curve},
    {"output", "-o,--output", false, T::Text, "", 0, 0, false, false, "", "", "PNG",
     "the charts to write; OUT.csv beside it (and with minCost the clump chosen, OUT_best.csv)", c::Ochart},
    {"output", "-o,--output", false, T::Text, "", 0, 0, false, false, "", "", "OUT",
     "the template to write (liggghts: an input-script file to include; kratos: a .clu cluster; mercurydpm: "
     "a "
     "folder; pfc: a .p3dat data file with clump template create; yade: a clumps .txt for readClumps)",
     c::Export},
    // a template for another DEM code: the grain's exact mass properties with the spheres
    {"format", "--format", true, T::Choice, "liggghts", 0, 0, false, false,
     "liggghts|kratos|mercurydpm|pfc|yade", "", "F", "the DEM code whose template is written", c::Export},
    {"density", "--density", true, T::Number, "1000", 0, kInf, true, true, "", "mass / world unit^3", "RHO",
     "the grain's density: the template's mass is it times the grain's exact volume", c::Export},
    {"frame", "--frame", true, T::Choice, "principal", 0, 0, false, false, "principal|generated", "", "FRAME",
     "the template's axes: the grain's principal axes of inertia, or the axes it was generated in "
     "(the centre of mass is the origin in both; pfc: the generated frame keeps the pebbles where they were "
     "generated, PFC moves them)",
     c::Export},
    {"templateType", "--type", true, T::Integer, "1", 1, 2000000, false, false, "", "", "N",
     "the template's number (LIGGGHTS: multisphere types are consecutive from 1)", c::Export},
    {"atomType", "--atom-type", true, T::Integer, "1", 1, kIntMax, false, false, "", "", "N",
     "the spheres' atom (material) type", c::Export},
    // the surface of a clump (mss surface): the mesh of its spheres' union
    {"output", "-o,--output", false, T::Text, "", 0, 0, false, false, "", "", "MESH",
     "the mesh to write: .stl (binary), .obj or .ply (binary)", c::Surface},
    {"tolerance", "--tolerance", true, T::Number, "0.002", 0, 0.5, true, true, "", "", "X",
     "refine until the mesh's volume is within this fraction of the union's exact volume", c::Surface},
    {"maxEdge", "--max-edge", true, T::Number, "0", 0, kInf, false, true, "", "world units", "L",
     "and until no edge is longer than this; 0: no bound", c::Surface},
    {"maxTriangles", "--max-triangles", true, T::Integer, "20000000", 1, kIntMax, false, false, "", "", "N",
     "refuse bounds that need more triangles than this", c::Surface},
    // heavy requests (mss/work.hpp): refused before they start past this, with the estimate
    {"maxWork", "--max-work", true, T::Number, "600", 0, kInf, true, true, "", "seconds", "S",
     "refuse a request whose estimated work (seconds on a 2-core machine) exceeds this, before it starts, "
     "naming the estimate; a long run shows its progress and stops on Ctrl-C",
     kGenerating | c::Compare | c::Surface | c::Preview | c::Curve | c::Ochart | c::Spheropolygon},
    // termination (paper section 3.5): generation stops at the first met
    {"nSpheres", "--spheres", true, T::Integer, "", 1, 65535, false, false, "", "", "N",
     "at most this many spheres (problem (i) of the paper, eq. 2)", kGenerating},
    {"eta", "--eta", true, T::Number, "", 0, 1, false, true, "", "", "X",
     "stop once the relative mismatch (eq. 7) is at most this (problem (ii), eq. 4); 0: no such target",
     kGen},
    {"dice", "--dice", true, T::Number, "", 0, 1, false, true, "", "", "X",
     "stop once the Dice mismatch (eq. 27) is at most this; 0: no such target", kGen},
    {"rMin", "--rmin", true, T::Number, "", 0, kInf, false, true, "", "world units", "R",
     "no sphere of a smaller radius; 0: no such bound", kGen},
    {"rMinVoxels", "--rmin-voxels", true, T::Number, "", 0, kInf, false, true, "", "voxels", "V",
     "no sphere of a radius under this many voxels of the generation grid (with rMin: the larger); 0: no "
     "such bound",
     kGen},
    {"maxIterations", "--max-iterations", true, T::Integer, "100", 1, kIntMax, false, false, "", "", "N",
     "cap on the iterations (paper method) or rounds of refinement (optimized)", kGen},
    // the grid
    {"voxelSize", "--voxel-size", true, T::Number, "", 0, kInf, true, true, "", "world units", "H",
     "voxel edge of the grid: a mesh's generation grid (instead of resolution), a voxel volume's own voxels "
     "(default 1)",
     kGrain},
    {"resolution", "--resolution", true, T::Integer, "100", 1, kIntMax, false, false, "", "voxels", "N",
     "a mesh's generation grid: this many voxels along the shortest bounding-box edge (the paper uses 205)",
     kGen},
    {"resolution", "--resolution", true, T::Integer, "100", 1, kIntMax, false, false, "", "voxels", "N",
     "the scoring grid: this many voxels along the grain's shortest bounding-box edge", c::Compare},
    {"resolution", "--resolution", true, T::Integer, "160", 1, kIntMax, false, false, "", "voxels", "N",
     "the pictures' grid: this many voxels along the grain's shortest bounding-box edge", c::Preview},
    {"resolution", "--resolution", true, T::Integer, "103", 1, kIntMax, false, false, "", "voxels", "N",
     "a mesh's generation grid: this many voxels along the shortest bounding-box edge (scored on a grid "
     "of 100, offset 0.37)",
     c::Curve | c::Ochart},
    {"supersample", "--supersample", true, T::Integer, "1", 1, 8, false, false, "", "", "K",
     "K^3 samples per voxel (K this) when voxelising a mesh (1: voxel centres)", kGen | c::Compare},
    {"memoryLimit", "--memory-limit", true, T::Number, "8", 0, kMaxMemoryGiB, true, false, "", "GiB", "GIB",
     "refuse a mesh's grid whose working memory would exceed this; mss batch reads a labelled volume "
     "in slabs of a 128th of it",
     kGen},
    {"scale", "--scale", true, T::Number, "1", 0, kInf, true, true, "", "", "S",
     "a factor on the grain's coordinates as read (1e-3: a mesh in millimetres becomes metres; a voxel "
     "volume: its voxel size and origin); the options in world units are in the scaled units",
     kGrain},
    {"origin", "--origin", true, T::Point, "", 0, 0, false, false, "", "world units", "X,Y,Z",
     "a voxel volume: the world position of the centre of voxel (0, 0, 0) (default 0,0,0)", kGrain},
    {"label", "--label", true, T::Integer, "", 0, kInt64Max, false, false, "", "", "L",
     "a labelled voxel volume: the solid is the voxels of this label (required when the volume holds "
     "several labels)",
     c::Generate | c::Compare | c::Info | c::Preview | c::Curve | c::Ochart | c::Export},
    // the method
    {"method", "--method", true, T::Choice, "optimized", 0, 0, false, false, "optimized|paper", "", "M",
     "optimized: MSS's candidates and a denser medial sampling, chosen greedily and tuned; paper: the "
     "published procedure (maxima of E, then of 2E - E~, eq. 25)",
     kGen},
    {"deltaMin", "--delta-min", true, T::Number, "1", 0, kInf, false, true, "", "voxels", "D",
     "paper method: least distance between sphere centres (section 3.4)", kGen},
    {"keepSymmetry", "--no-symmetry", true, T::Flag, "true", 0, 0, false, false, "", "", "",
     "detect the grain's mirror planes and keep them (optimized method)", kGen},
    {"polish", "--polish", true, T::Flag, "false", 0, 0, false, false, "", "", "",
     "move all centres and radii together as a last stage, by the gradient of a smoothed mismatch, and "
     "refine again (optimized method): a lower D at a fixed count, for 2-5 times the time",
     kGen},
    {"contacts", "--no-contacts", true, T::Flag, "true", 0, 0, false, false, "", "", "",
     "a labelled volume: keep the grain's contacts with its neighbours (each one's spheres reach a point of "
     "the faces they share, so that grains touching in the scan touch in the assembly)",
     kGenerating},
    {"contactGap", "--contact-gap", true, T::Number, "1", 0, 8, false, false, "", "voxels", "V",
     "a labelled volume: two grains are in contact where their voxels come within this many voxels (1 covers "
     "the separating lines of a watershed and the labels of a binary scan; each grain's spheres then reach "
     "the middle of the gap); 0: shared faces only",
     kGenerating},
    {"neighbourProtrusion", "--neighbour-protrusion", true, T::Number, "1", 0, 1, false, false, "", "", "F",
     "a labelled volume's grain: the share of the protrusion bound its spheres may reach into a neighbouring "
     "grain (0.5: two neighbours' clumps overlap by at most the bound, at a cost in D; 1: as elsewhere)",
     kGenerating},
    {"threads", "--threads", true, T::Integer, "0", 0, 1024, false, false, "", "", "T",
     "OpenMP threads, 0: OpenMP's default; the result does not depend on it", c::Generate | c::Export},
    // the bound on protrusion (paper section 3.5)
    {"clip", "--clip", true, T::Flag, "false", 0, 0, false, false, "", "", "",
     "no sphere protrudes from the grain (a mesh: the exact distance to its surface; a voxel volume: the "
     "faces of its solid voxels)",
     kGen},
    {"maxProtrusion", "--max-protrusion", true, T::Number, "", 0, kInf, false, false, "", "world units", "H",
     "no point of a sphere farther than this beyond the grain (the radius is at most the exact distance "
     "from the centre to the surface plus this); default: one voxel of the generation grid, the paper's "
     "tolerance; 0: as clip; inf: unbounded",
     kGen | c::Curve | c::Ochart},
    {"refill", "--no-refill", true, T::Flag, "true", 0, 0, false, false, "", "", "",
     "with clip or a protrusion bound: choose the spheres under it, regaining the coverage it costs (off: "
     "generate freely, then shrink the radii)",
     kGen},
    {"planes", "--plane", true, T::Planes, "", 0, 0, false, false, "", "world units", "PX,PY,PZ,NX,NY,NZ",
     "planes no sphere crosses, each a point and a normal (spheres stay on the normal's side; the flag may "
     "repeat); planes that cut the grain make the target its part on their side (a fragment)",
     c::Generate | c::Compare | c::Export},
    // comparing
    {"offset", "--offset", true, T::Number, "0.37", -kInf, kInf, true, true, "", "voxels", "F",
     "shift of the scoring grid against the grain's bounding box", c::Compare},
    {"align", "--align", true, T::Choice, "", 0, 0, false, false, "centroid|bbox|principal|none", "", "MODE",
     "register the spheres first (centroid, bbox, principal); none: as written, even in another frame; "
     "default: as written, a set in another frame refused",
     c::Compare},
    {"clumpId", "--clump", true, T::Integer, "", 0, kInt64Max, false, false, "", "", "ID",
     "the clump with this id, of a YADE text file of several", c::Compare | c::Surface},
    {"csv", "--csv", false, T::Text, "", 0, 0, false, false, "", "", "OUT", "also write the rows as CSV",
     c::Compare},
    {"exact", "--exact", true, T::Flag, "false", 0, 0, false, false, "", "", "",
     "also score on the exact shapes by Monte Carlo (the mesh's winding number, the spheres), with standard "
     "errors: no lattice bias",
     c::Compare},
    {"samples", "--samples", true, T::Integer, "1000000", 1000, 1e9, false, false, "", "", "N",
     "--exact: the Monte Carlo points (the standard error falls as 1 / sqrt(N))", c::Compare},
    {"seed", "--seed", true, T::Integer, "1", 0, kInt64Max, false, false, "", "", "S",
     "--exact: the points' seed (the same seed, the same points on any machine and thread count)",
     c::Compare},
    // pictures
    {"preview", "--preview", false, T::Text, "", 0, 0, false, false, "", "", "PNG",
     "also draw the clump against the grain (as mss preview)", c::Generate},
    {"previews", "--previews", true, T::Flag, "false", 0, 0, false, false, "", "", "",
     "draw the grains worth a look (as mss preview: the flagged ones, worst first, at most 12) into "
     "report.html",
     c::Batch},
    {"counts", "--counts", true, T::Text, "", 0, 0, false, false, "", "", "A:B",
     "the range of sphere counts (log-spaced, both ends included)", c::Curve | c::Ochart},
    {"points", "--points", true, T::Integer, "12", 2, 1000, false, false, "", "", "N",
     "sphere counts in the range", c::Curve},
    {"points", "--points", true, T::Integer, "6", 2, 100, false, false, "", "", "N",
     "sphere counts in the range", c::Ochart},
    {"radii", "--radii", true, T::Text, "0.05:0.6", 0, 0, false, false, "", "", "A:B",
     "the range of the radius bound rMin, fractions of the grain's largest inscribed radius (log-spaced, "
     "both ends included)",
     c::Ochart},
    {"radiusPoints", "--radius-points", true, T::Integer, "5", 2, 100, false, false, "", "", "M",
     "radius bounds in the range", c::Ochart},
    {"dice", "--dice", true, T::Number, "", 0, 1, true, true, "", "", "X",
     "with minCost: the fidelity to meet, D <= X on the scoring grid", c::Ochart},
    {"minCost", "--min-cost", true, T::Flag, "false", 0, 0, false, false, "", "", "",
     "choose the clump of least cost n / r_min among the chart's points meeting dice (problem (iii))",
     c::Ochart},
    {"compare", "--compare", true, T::Files, "", 0, 0, false, false, "", "", "SPHERES",
     "sphere files of other generators, drawn as points", c::Curve},
    // a batch
    {"workers", "--workers", true, T::Integer, "", 1, 1024, false, false, "", "", "N",
     "processes side by side (default: the cores other processes leave free, at least 1; never more than "
     "the grains)",
     c::Batch},
    {"scheduler", "--scheduler", true, T::Text, "", 0, 0, false, false, "", "", "URL",
     "tls://HOST:PORT (or tcp://) of a Dask scheduler: grains as its tasks. Without TLS anyone who reaches "
     "the port runs code as the workers' user",
     c::Batch},
    {"connectTimeout", "--connect-timeout", true, T::Number, "5", 0, 600, true, false, "", "seconds", "S",
     "give up on a Dask scheduler that does not answer within this, naming its address", c::Batch},
    {"tlsCaFile", "--tls-ca-file", false, T::Text, "", 0, 0, false, false, "", "", "PEM",
     "TLS: the CA certificate the cluster trusts", c::Batch},
    {"tlsCert", "--tls-cert", false, T::Text, "", 0, 0, false, false, "", "", "PEM",
     "TLS: this client's certificate", c::Batch},
    {"tlsKey", "--tls-key", false, T::Text, "", 0, 0, false, false, "", "", "PEM",
     "TLS: this client's private key", c::Batch},
    {"minVoxels", "--min-voxels", true, T::Integer, "0", 0, kInt64Max, false, false, "", "voxels", "N",
     "skip grains of fewer voxels", c::Batch},
    {"excludeBorder", "--exclude-border", true, T::Flag, "false", 0, 0, false, false, "", "", "",
     "skip grains cut by the volume's border", c::Batch},
    {"segment", "--segment", true, T::Flag, "false", 0, 0, false, false, "", "", "",
     "the volume is a binary scan (two values): segment it into grains first (specks dropped, pores filled "
     "for its distance transform, a marker watershed of the transform's maxima, neighbours joined where the "
     "pass between them nears their peaks: nothing in voxels to tune); segments under --min-voxels are "
     "dropped; the labels are written to OUT/labels.npy to inspect or correct",
     c::Batch},
    {"segmentH", "--segment-h", true, T::Number, "", 0, 1000, true, false, "", "voxels", "H",
     "with segment: instead of the default, a maximum of the distance transform is a grain's marker when it "
     "stands this much above the saddles around it (larger: fewer, larger grains)",
     c::Batch},
    {"segmentMarkers", "--segment-markers", true, T::Text, "", 0, 0, false, false, "", "", "NPY",
     "with segment: a label volume of markers of your own (the scan's shape; non-zero voxels seed a grain "
     "each label), grown by the watershed instead of the transform's maxima",
     c::Batch},
    // the time step each grain allows (YADE's PWaveTimeStep: the smallest radius times sqrt(density / young))
    {"density", "--density", true, T::Number, "1000", 0, kInf, true, true, "", "mass / world unit^3", "RHO",
     "the grains' density, for the time step each allows and the templates' mass (default: YADE's FrictMat)",
     c::Batch},
    {"format", "--format", true, T::Choice, "", 0, 0, false, false, "liggghts|kratos|mercurydpm|pfc|yade", "",
     "F",
     "also write each grain as this DEM code's template (templates/, as mss export) and where each goes "
     "(placements.csv)",
     c::Batch},
    {"young", "--young", true, T::Number, "1e9", 0, kInf, true, true, "", "mass / (world unit s^2)", "E",
     "the grains' Young's modulus, for the time step each allows (default: YADE's FrictMat)", c::Batch},
    // spheropolygons (2-D, the second paper)
    {"output", "-o,--output", false, T::Text, "", 0, 0, false, false, "", "", "JSON", "the JSON to write",
     c::Spheropolygon},
    {"vertices", "--vertices", true, T::Integer, "30", 3, 10000, false, false, "", "", "N",
     "vertices of the spheropolygon", c::Spheropolygon},
    {"radius", "--radius", true, T::Number, "", 0, kInf, true, true, "", "world units", "R",
     "the spheroradius; default: the one of least error", c::Spheropolygon},
    {"init", "--init", true, T::Choice, "auto", 0, 0, false, false, "auto|circle|boundary|curvature", "",
     "INIT", "where the vertices start (section 3.1); auto: boundary and curvature both, the better kept",
     c::Spheropolygon},
    {"threshold", "--threshold", false, T::Number, "", -kInf, kInf, true, true, "", "", "G",
     "a PNG: the grey level under which a pixel is particle (default: halfway)", c::Spheropolygon},
    {"pixelSize", "--pixel-size", true, T::Number, "1", 0, kInf, true, true, "", "world units", "H",
     "a pixel's edge", c::Spheropolygon},
    {"origin", "--origin", true, T::Point2, "0,0", 0, 0, false, false, "", "world units", "X,Y",
     "the world position of the centre of pixel [0, 0]", c::Spheropolygon},
    {"ochart", "--ochart", false, T::Text, "", 0, 0, false, false, "", "", "DIR",
     "also sweep N and r into this folder: the error, the cost and O as CSV and the three charts (Fig. 4)",
     c::Spheropolygon},
    {"preview", "--preview", false, T::Text, "", 0, 0, false, false, "", "", "PNG",
     "also draw the result over the image", c::Spheropolygon},
    {"vertexRadii", "--vertex-radii", true, T::Flag, "false", 0, 0, false, false, "", "", "",
     "a spheroradius per vertex (3N parameters), none below minRadius", c::Spheropolygon},
    {"minRadius", "--min-radius", true, T::Number, "", 0, kInf, false, true, "", "world units", "R",
     "with vertexRadii: the least radius (default: the spheroradius)", c::Spheropolygon},
    {"regionVertices", "--region-vertices", true, T::Flag, "false", 0, 0, false, false, "", "", "",
     "at least one vertex in every convex or concave region of the boundary", c::Spheropolygon},
    {"regionTurning", "--region-turning", true, T::Number, "", 0, 360, true, false, "", "degrees", "DEG",
     "with regionVertices: how far a stretch of the boundary must turn to be a region (default 90)",
     c::Spheropolygon},
    {"labels", "--labels", false, T::Text, "", 0, 0, false, false, "", "", "L1,L2,...",
     "only these labels of a labelled volume", c::Batch},
    // a triaxial test of the grains (mss triaxial; Python yade_mss.studies): SI units
    {"output", "-o,--output", false, T::Text, "", 0, 0, false, false, "", "", "DIR",
     "the output folder: triaxial.csv, summary.csv and .json, the pictures, report.html, runs/ (a rerun "
     "resumes in it)",
     c::Triaxial},
    {"nSpheres", "--spheres", true, T::Integer, "10", 1, 65535, false, false, "", "", "N",
     "at most this many spheres a grain (eq. 2); several, N,N,... (Python: a list), test the same specimen "
     "at each count",
     c::Triaxial},
    {"grain", "--grain", true, T::Text, "", 0, 0, false, false, "", "", "GRAIN",
     "an input that is a sphere file (another generator's): the grain it stands for, for the exact mass",
     c::Triaxial},
    {"grains", "--grains", true, T::Integer, "200", 2, 100000, false, false, "", "", "N",
     "clumps in the periodic cell", c::Triaxial},
    {"confining", "--confining", true, T::Number, "100e3", 0, kInf, true, true, "", "Pa", "P",
     "the confining pressure: the compaction's goal, then the lateral stress (drained)", c::Triaxial},
    {"state", "--state", true, T::Choice, "dense", 0, 0, false, false, "dense|loose", "", "S",
     "the state compaction makes: dense (compacted without friction) or loose (with it)", c::Triaxial},
    {"strain", "--strain", true, T::Number, "0.2", 0, 0.9, true, true, "", "", "E",
     "the axial strain (compression positive) at which shearing stops", c::Triaxial},
    {"undrained", "--undrained", true, T::Flag, "false", 0, 0, false, false, "", "", "",
     "shear at constant volume (default: drained, constant lateral stress)", c::Triaxial},
    {"seed", "--seed", true, T::Integer, "1", 0, kInt64Max, false, false, "", "", "S",
     "the specimen's places, orientations and grains (the same for every sphere count)", c::Triaxial},
    {"density", "--density", true, T::Number, "2650", 0, kInf, true, true, "", "mass / world unit^3", "RHO",
     "the grains' density (SI: kg/m^3)", c::Triaxial},
    {"young", "--young", true, T::Number, "1e8", 0, kInf, true, true, "", "mass / (world unit s^2)", "E",
     "the spheres' Young's modulus (SI: Pa; YADE's FrictMat: a contact's stiffness is about young times its "
     "radius)",
     c::Triaxial},
    {"poisson", "--poisson", true, T::Number, "0.3", -1, 0.5, false, false, "", "", "NU",
     "YADE's FrictMat poisson: a contact's shear over normal stiffness", c::Triaxial},
    {"frictionAngle", "--friction", true, T::Number, "0.5", 0, 1.5707963267948966, false, false, "",
     "radians", "PHI", "the contacts' friction angle while sheared (YADE's FrictMat frictionAngle)",
     c::Triaxial},
    {"inertialNumber", "--inertial-number", true, T::Number, "5e-4", 0, 0.1, true, false, "", "", "I",
     "the inertial number I = rate d sqrt(density / p) at the confining pressure: sets the strain rate "
     "(quasi-static: I under 1e-3)",
     c::Triaxial},
    {"damping", "--damping", true, T::Number, "0.2", 0, 0.99, false, false, "", "", "D",
     "YADE's NewtonIntegrator local damping", c::Triaxial},
    {"records", "--records", true, T::Integer, "200", 10, 100000, false, false, "", "", "N",
     "records over the axial strain", c::Triaxial},
    {"compactionSteps", "--compaction-steps", true, T::Integer, "", 100, kIntMax, false, false, "", "", "N",
     "give up a compaction that has not reached the confining pressure in this many steps, saying so "
     "(default 200,000 + 50 a grain)",
     c::Triaxial},
    {"workers", "--workers", true, T::Integer, "", 1, 1024, false, false, "", "", "N",
     "sphere counts run side by side (default: the cores other processes leave free, at least 1)",
     c::Triaxial},
    {"scheduler", "--scheduler", true, T::Text, "", 0, 0, false, false, "", "", "URL",
     "tcp:// or tls://HOST:PORT of a Dask scheduler: each sphere count a task on its workers (YADE and "
     "yade_mss installed there)",
     c::Triaxial},
    {"contactStiffness", "--contact-stiffness", true, T::Choice, "spheres", 0, 0, false, false,
     "spheres|grain", "", "K",
     "spheres: YADE's own (each member contact its spheres' stiffness: a clump pair stiffens with the sphere "
     "count); grain: each pair of bodies one contact of their grains' stiffness, whatever the count "
     "(yade_mss.contactStiffnessEngine)",
     c::Triaxial},
    {"quiet", "--quiet", true, T::Flag, "false", 0, 0, false, false, "", "", "",
     "no progress line (the summary is printed all the same)", c::Triaxial},
    {"maxWork", "--max-work", true, T::Number, "7200", 0, kInf, true, true, "", "seconds", "S",
     "refuse a study whose estimated wall time (seconds on a 2-core machine, the counts side by side) "
     "exceeds this, before it starts, naming the estimate",
     c::Triaxial},
};

} // namespace

const std::vector<OptionSpec>& optionTable() {
    return kTable;
}

} // namespace mss
