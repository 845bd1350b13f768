// mss: command-line front end of the yade-mss core.
#include "mss.hpp"
#include "mss/core/mesh_query.hpp"
#include "mss/io/atomic_file.hpp"
#include "mss/platform/cores.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <malloc.h>
#include <map>
#include <new>
#include <sched.h>
#include <sstream>
#include <stdexcept>
#include <string>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace {

/// What the command line gave, as text by option name (the option table's); --plane may repeat.
struct Args {
    std::vector<std::string> positional;
    std::vector<std::string> planes;
    std::map<std::string, std::string> opts;
    bool has(const std::string& k) const { return opts.count(k) != 0; }
    const std::string& text(const std::string& k) const { return opts.at(k); }
};

/// The command line's spelling of an option: its long flag.
std::string flagOf(const std::string& name) {
    const mss::OptionSpec* s = mss::findOption(name);
    if (!s) return name;
    const std::string f = s->flag;
    return f.substr(f.rfind(',') + 1);
}

/// A core message with the options it names ("the option label") spelled as the command line spells them.
std::string spelled(std::string message) {
    for (const mss::OptionSpec& s : mss::optionTable()) {
        const std::string named = std::string("the option ") + s.name;
        for (std::size_t at = message.find(named); at != std::string::npos; at = message.find(named, at)) {
            const std::size_t end = at + named.size();
            if (end < message.size() && std::isalnum(static_cast<unsigned char>(message[end]))) {
                at = end; // a longer name ("labels")
                continue;
            }
            message.replace(at, named.size(), flagOf(s.name));
        }
    }
    return message;
}

/// The values given to command @p cmd, each parsed as the table's row says. @throws mss::OptionError
mss::OptionValues values(const Args& a, unsigned cmd) {
    mss::OptionValues v;
    for (const auto& [name, text] : a.opts) {
        const mss::OptionSpec* s = mss::findOption(name, cmd);
        if (s && s->type != mss::OptionType::Text) v[name] = mss::parseOption(*s, text);
    }
    if (!a.planes.empty()) {
        std::vector<mss::Plane> all;
        for (const std::string& text : a.planes) {
            const auto p =
                std::get<std::vector<mss::Plane>>(mss::parseOption(*mss::findOption("planes"), text));
            all.insert(all.end(), p.begin(), p.end());
        }
        v["planes"] = all;
    }
    return v;
}

/// The cores this process might use before its threads were pinned (mss::spreadThreads), when they were.
struct Unpinned {
    bool pinned = false;
    cpu_set_t mask{};
};
Unpinned& unpinned() {
    static Unpinned u;
    return u;
}

/// Whether this is the build tree's command (not the installed one): then its Python package is the build
/// tree's.
bool runFromBuildTree() {
    char exe[4096];
    const ssize_t n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);
    if (n <= 0) return false;
    exe[n] = '\0';
    char* build = realpath(MSS_BUILD_DIR, nullptr);
    if (!build) return false;
    const std::string dir = std::string(build) + "/";
    std::free(build);
    return std::string(exe).compare(0, dir.size(), dir) == 0;
}

/// The python3 child of runPython, for the signal handler below (0: none yet).
volatile sig_atomic_t gChild = 0;

/// SIGTERM, and a SIGINT sent to this process alone (kill -INT, timeout -s INT, a job scheduler), go on to
/// the child, which stops as on Ctrl-C and says so; a terminal's Ctrl-C (SI_KERNEL) reaches the child by
/// itself, through the process group, and is not sent twice.
extern "C" void forwardSignal(int sig, siginfo_t* info, void*) {
    if (gChild <= 0) return;
    if (sig == SIGINT && info && info->si_code != SI_USER) return;
    kill(pid_t(gChild), sig);
}

/// Runs `python3 -m yade_mss COMMAND ...` (Debian's python3): the commands drawn with matplotlib (`mss
/// preview`, `mss curve`, `mss generate --preview`) and the batch (`mss batch`). The build tree's command
/// puts the build tree's package first, so an uninstalled build draws with its own code; the installed
/// command runs the installed package. The child dies with this process (a killed `mss batch` leaves no batch
/// running).
/// @return the exit status.
int runPython(const std::vector<std::string>& args) {
    std::string path;
    if (runFromBuildTree()) path = MSS_PY_BUILD_DIR;
    if (const char* old = std::getenv("PYTHONPATH")) path += (path.empty() ? "" : ":") + std::string(old);
    const pid_t parent = getpid();
    const pid_t pid = fork();
    if (pid < 0) throw std::runtime_error("cannot start python3 for the pictures");
    if (pid == 0) {
        prctl(PR_SET_PDEATHSIG, SIGTERM);
        if (getppid() != parent) _exit(1); // the parent died before the line above
        // a child inherits its parent thread's cores: python (and a batch's Dask workers) gets them all back
        if (unpinned().pinned) sched_setaffinity(0, sizeof(cpu_set_t), &unpinned().mask);
        if (path.empty())
            unsetenv("PYTHONPATH");
        else
            setenv("PYTHONPATH", path.c_str(), 1);
        std::vector<std::string> all{MSS_PYTHON, "-m", "yade_mss"};
        all.insert(all.end(), args.begin(), args.end());
        std::vector<char*> argv;
        for (std::string& a : all) argv.push_back(a.data());
        argv.push_back(nullptr);
        execv(MSS_PYTHON, argv.data());
        std::perror("mss: cannot run " MSS_PYTHON);
        _exit(127);
    }
    // Ctrl-C reaches the child too (one process group): the child stops cleanly and says so, this one waits;
    // a signal meant for the whole job but sent to this process alone is passed on (forwardSignal)
    gChild = pid;
    struct sigaction sa {};
    sa.sa_sigaction = forwardSignal;
    sa.sa_flags = SA_SIGINFO | SA_RESTART;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}

/// Ctrl-C: the running step stops at its next checkpoint (mss::Interrupted), publishing nothing; a second
/// Ctrl-C ends the program at once.
extern "C" void onInterrupt(int) {
    mss::requestStop();
    std::signal(SIGINT, SIG_DFL);
}

/// Writes @p text to @p path whole or not at all (an exclusive temporary file, then a rename; only a regular
/// file or a new path is replaced).
void writeTextAtomically(const std::string& path, const std::string& text) {
    mss::detail::writeFileAtomically("mss", path, text);
}

/// Runs @p f; an error that does not name the input file gets it in front (the core's "the solid is flat"
/// does not know the file).
template <class F> auto namingInput(const std::string& in, F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        if (what.find(in) != std::string::npos) throw;
        throw std::invalid_argument(in + ": " + what);
    }
}

/// Whether @p path is a voxel volume (the format table's); one the core does not read is refused by name.
/// A file written beside its final path under a fresh name (created exclusively, the same extension: the
/// writers go by it) and renamed onto it by publish(); removed if never published.
class PendingFile {
public:
    explicit PendingFile(const std::string& target) : target_(target) {
        const std::string dir =
            target.find('/') == std::string::npos ? "." : target.substr(0, target.rfind('/'));
        const std::string ext = mss::fileExtension(target);
        std::string name = dir + "/.mss-pending-XXXXXX" + ext;
        std::vector<char> buf(name.begin(), name.end());
        buf.push_back('\0');
        const int fd = ::mkstemps(buf.data(), int(ext.size()));
        if (fd < 0)
            throw std::invalid_argument("generate: " + target + ": cannot write beside it (" +
                                        std::strerror(errno) + ")");
        ::close(fd);
        path = buf.data();
    }
    ~PendingFile() {
        if (!published_) ::unlink(path.c_str());
    }
    PendingFile(const PendingFile&) = delete;
    PendingFile& operator=(const PendingFile&) = delete;
    void publish() const {
        if (std::rename(path.c_str(), target_.c_str()) != 0)
            throw std::invalid_argument("generate: " + target_ + ": cannot write (" + std::strerror(errno) +
                                        ")");
        published_ = true;
    }
    std::string path;

private:
    std::string target_;
    mutable bool published_ = false;
};

bool isVoxelFile(const std::string& path) {
    const mss::FileFormat* f = mss::findFormat(path, mss::FileKind::Voxels);
    if (f && !f->readByCore)
        throw std::invalid_argument(path + ": " + f->extension +
                                    " stacks are read by the Python package (mss batch, mssClump, "
                                    "generate()); this command reads " +
                                    mss::formatList(mss::FileKind::Voxels) + " volumes");
    return f != nullptr;
}

/// Refuses a --scale that makes a grain's coordinates too large (@p far: the farthest coordinate, scaled) or
/// its size underflow (@p size, scaled: under 1e-290 a double has lost its digits, the grain voxelises to
/// nothing and a good mesh reads as degenerate), naming --scale rather than a vertex or the triangles.
std::string shortNumber(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}

void checkScaled(double scale, double size, double far, const std::string& what) {
    const std::string hint =
        ": --scale is the unit conversion of the coordinates (1e-3 for millimetres to metres)";
    std::ostringstream s;
    s << "--scale " << scale << ": " << what;
    if (!std::isfinite(size) || !(far <= 1e60))
        throw std::invalid_argument(s.str() + " times the scale reaches " + shortNumber(far) +
                                    ", beyond 1e60 (where a grain's inertia, as size^5, overflows)" + hint);
    if (size < 1e-290) {
        s << " times the scale is " << size << ", under 1e-290: the grain would vanish";
        throw std::invalid_argument(s.str() + hint);
    }
}

/// A voxel volume's voxel edge and origin as read, times --scale.
double scaledVoxelSize(const mss::Settings& st) {
    const double h = (st.voxelSize > 0 ? st.voxelSize : 1.0);
    if (st.scale != 1.0)
        checkScaled(st.scale, h * st.scale, st.origin.cwiseAbs().maxCoeff() * st.scale,
                    "the voxel edge " + shortNumber(h));
    return h * st.scale;
}

mss::VoxelGrid readVoxels(const mss::Settings& st, const std::string& path) {
    return mss::readNpy(path, scaledVoxelSize(st), st.origin * st.scale, st.label);
}

/// A mesh file with its vertices times --scale (a mesh in millimetres to metres).
mss::TriangleMesh readScaledMesh(const mss::Settings& st, const std::string& path) {
    mss::TriangleMesh mesh = mss::readMesh(path);
    if (st.scale != 1.0 && !mesh.vertices.empty()) {
        mss::Vec3 lo = mesh.vertices[0], hi = lo;
        double far = 0.0;
        for (const mss::Vec3& v : mesh.vertices) {
            lo = lo.cwiseMin(v);
            hi = hi.cwiseMax(v);
            far = std::max(far, v.cwiseAbs().maxCoeff());
        }
        const double extent = (hi - lo).maxCoeff();
        checkScaled(st.scale, extent * st.scale, far * st.scale, "the mesh's extent " + shortNumber(extent));
        for (mss::Vec3& v : mesh.vertices) v *= st.scale;
    }
    return mesh;
}

/// The other grains near @p label, on its bounding box widened by 2 voxels (the grid mss batch gives it;
/// beyond the volume nobody): where its spheres may protrude by half the bound only.
mss::VoxelGrid neighboursOf(const mss::LabelGrid& g, long long label) {
    std::array<int, 3> lo{g.spec.dims}, hi{0, 0, 0};
    for (int k = 0; k < g.spec.dims[2]; ++k)
        for (int j = 0; j < g.spec.dims[1]; ++j)
            for (int i = 0; i < g.spec.dims[0]; ++i)
                if (g.labels[g.spec.index(i, j, k)] == label) {
                    const int at[3] = {i, j, k};
                    for (int a = 0; a < 3; ++a)
                        lo[std::size_t(a)] = std::min(lo[std::size_t(a)], at[a]),
                        hi[std::size_t(a)] = std::max(hi[std::size_t(a)], at[a] + 1);
                }
    mss::GridSpec s;
    for (int a = 0; a < 3; ++a) {
        lo[std::size_t(a)] -= 2;
        hi[std::size_t(a)] += 2;
        s.dims[std::size_t(a)] = std::max(0, hi[std::size_t(a)] - lo[std::size_t(a)]);
    }
    s.h = g.spec.h;
    s.origin = g.spec.origin + g.spec.h * mss::Vec3(lo[0], lo[1], lo[2]);
    mss::VoxelGrid out(s, 0);
    for (int k = 0; k < s.dims[2]; ++k)
        for (int j = 0; j < s.dims[1]; ++j)
            for (int i = 0; i < s.dims[0]; ++i) {
                const int x = i + lo[0], y = j + lo[1], z = k + lo[2];
                if (!g.spec.contains(x, y, z)) continue;
                const std::int64_t v = g.labels[g.spec.index(x, y, z)];
                out(i, j, k) = v != 0 && v != label;
            }
    return out;
}

/// Refuses, for a mesh, the options that only voxel volumes take (they would be ignored).
void voxelOptionsOnly(const Args& a, const std::string& in, std::initializer_list<const char*> names) {
    for (const char* name : names)
        if (a.has(name))
            throw std::invalid_argument(in + ": " + flagOf(name) +
                                        " applies to voxel volumes (.npy); this is a mesh");
}

void printMetrics(const mss::Result& r) {
    const auto& m = r.metrics;
    std::cout << std::setprecision(6);
    std::cout << "grid        " << r.grid.dims[0] << " x " << r.grid.dims[1] << " x " << r.grid.dims[2]
              << "  voxel size " << r.grid.h << "\n";
    std::cout << "spheres     " << m.spheres << "\n";
    std::cout << "eta         " << m.eta << "   (relative mismatch, eq. 7, generation grid)\n";
    std::cout << "dice        " << m.dice << "   (Dice mismatch, eq. 27, generation grid)\n";
    std::cout << "iterations  " << m.iterations << "   symmetry planes kept " << m.symmetryPlanes << "\n";
    if (m.clipped) std::cout << "clipped     " << m.clipped << " spheres shrunk by the final clipping\n";
    std::cout << "protrusion  " << m.protrusion
              << "   (largest beyond the grain, world units, <= " << m.protrusionLimit << ")\n";
    if (m.contacts)
        std::cout << "contacts    " << m.contacts << " with neighbours, " << m.contactsAdded
                  << " spheres added to reach them"
                  << (m.contactsMissed ? ", " + std::to_string(m.contactsMissed) + " not reached" : "")
                  << "\n";
    std::cout << "smallest r  " << m.smallestRadius << "   (world units; " << m.smallestRadius / r.grid.h
              << " voxels: it sets the time step)\n";
    std::cout << std::setprecision(3) << "seconds     read " << m.secondsRead << "  voxelize "
              << m.secondsVoxelize << "  edt " << m.secondsEdt << "  select " << m.secondsSelect
              << "  refine " << m.secondsRefine << "  total " << m.secondsTotal << "\n";
}

/// The DEM code whose template the extension of generate's output names, where that is unambiguous: a
/// template that takes no density (Kratos' and PFC's scale by the material's); "" for none. LIGGGHTS' .in and
/// MercuryDPM's folder need a density, and .txt is already YADE's text clump: those are mss export's.
std::string templateFormat(const std::string& path) {
    const std::string ext = mss::fileExtension(path);
    return ext == ".clu" ? "kratos" : ext == ".p3dat" ? "pfc" : "";
}

/// generate -o T.clu|T.p3dat: the generation's options passed to `mss export` (which writes the template
/// with the grain's exact mass properties); an option export does not take is refused by name first.
int generateTemplate(const Args& a, const std::string& format) {
    std::vector<std::string> args{"export", a.positional[0], "--format", format};
    for (const auto& [name, text] : a.opts) {
        const mss::OptionSpec* s = mss::findOption(name, mss::command::Generate);
        if (name == "output") {
            args.insert(args.end(), {"-o", text});
        } else if (!s || !(s->commands & mss::command::Export)) {
            throw std::invalid_argument(flagOf(name) + " does not apply to a template (-o " +
                                        a.text("output") + " runs mss export)");
        } else if (s->type == mss::OptionType::Flag) {
            if (text != s->fallback) args.push_back(flagOf(name));
        } else {
            args.insert(args.end(), {flagOf(name), text});
        }
    }
    for (const std::string& p : a.planes) args.insert(args.end(), {"--plane", p});
    return runPython(args);
}

int cmdGenerate(const Args& a) {
    if (a.positional.size() != 1) throw std::invalid_argument("generate needs one INPUT file");
    const std::string written = mss::formatList(mss::FileKind::Spheres, true);
    if (!a.has("output")) throw std::invalid_argument("generate needs -o OUT (" + written + ")");
    const std::string in = a.positional[0], out = a.text("output");
    std::vector<std::pair<std::string, std::string>> outputs{{"-o", out}};
    if (a.has("preview")) outputs.push_back({"--preview", a.text("preview")});
    mss::detail::refuseOverInputs("generate", outputs, {in});
    if (const std::string format = templateFormat(out); !format.empty()) return generateTemplate(a, format);
    {
        const mss::FileFormat* f = mss::findFormat(out, mss::FileKind::Spheres);
        if (!f || !f->formatSpheres)
            throw std::invalid_argument(out + ": unknown output extension '" + mss::fileExtension(out) +
                                        "' (expected " + written +
                                        "); a template with the grain's mass properties: .clu (Kratos) or "
                                        ".p3dat (PFC), or mss export");
    }
    const mss::Settings st = mss::settingsFrom(values(a, mss::command::Generate), mss::command::Generate);
    mss::GenerateOptions o = st.generate;
    mss::validateOptions(o);
    const auto t0 = std::chrono::steady_clock::now();
    mss::Result r;
    if (isVoxelFile(in)) {
        if (a.has("resolution"))
            throw std::invalid_argument(in +
                                        ": --resolution applies to meshes; a voxel volume is used at its "
                                        "own voxels (--voxel-size sets their edge)");
        const mss::VoxelGrid v = readVoxels(st, in);
        if (st.label >= 0 && st.keepContacts) { // the grain's neighbours, as mss batch finds them
            const mss::LabelGrid labels = mss::readNpyLabels(in, scaledVoxelSize(st), st.origin * st.scale);
            o.contacts = mss::contactPointsOf(mss::findContacts(labels, st.contactGap), st.label);
            o.neighbours = neighboursOf(labels, st.label);
        }
        const double tRead = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        r = mss::generate(v, o);
        r.metrics.secondsRead = tRead;
    } else {
        voxelOptionsOnly(a, in, {"label", "origin"});
        const mss::TriangleMesh mesh = readScaledMesh(st, in);
        const double tRead = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        r = namingInput(in, [&] { return mss::generate(mesh, st.resolution, o, st.supersample); });
        r.metrics.secondsRead = tRead;
    }
    for (const std::string& w : r.metrics.warnings)
        std::cerr << "mss generate: warning: " << in << ": " << w << "\n";
    if (!a.has("preview")) {
        mss::writeSpheres(r.spheres, out);
    } else { // the spheres are published only once their preview is drawn: a failed command leaves no output
        const PendingFile pending(out);
        mss::writeSpheres(r.spheres, pending.path);
        std::vector<std::string> args{"preview", in, pending.path, "-o", a.text("preview")};
        // titled by the file it will be, not by the pending file's name
        args.insert(args.end(), {"--title", out.substr(out.find_last_of('/') + 1)});
        for (const char* k : {"voxelSize", "origin", "label"})
            if (a.has(k) && isVoxelFile(in)) args.insert(args.end(), {flagOf(k), a.text(k)});
        if (a.has("scale")) args.insert(args.end(), {flagOf("scale"), a.text("scale")});
        if (runPython(args) != 0) throw std::runtime_error("the preview could not be drawn (see above)");
        pending.publish();
    }
    r.metrics.secondsTotal = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    printMetrics(r);
    std::cout << "wrote       " << out << std::endl;
    return 0;
}

void printComparison(const mss::Comparison& c) {
    const mss::Score& sc = c.score;
    std::cout << std::setprecision(6);
    std::cout << "grid          " << sc.grid.dims[0] << " x " << sc.grid.dims[1] << " x " << sc.grid.dims[2]
              << "  voxel size " << sc.grid.h << "\n";
    if (c.transform.translation.norm() > 0 || !c.transform.rotation.isIdentity()) {
        const Eigen::Matrix3d& R = c.transform.rotation;
        const mss::Vec3& t = c.transform.translation;
        std::cout << "aligned       x' = R x + t, t = " << t.x() << " " << t.y() << " " << t.z()
                  << ", R rows " << R(0, 0) << " " << R(0, 1) << " " << R(0, 2) << " | " << R(1, 0) << " "
                  << R(1, 1) << " " << R(1, 2) << " | " << R(2, 0) << " " << R(2, 1) << " " << R(2, 2)
                  << "\n";
    }
    std::cout << "spheres       " << c.spheres << "\n";
    std::cout << "dice          " << sc.dice << "\n";
    std::cout << "eta           " << sc.eta << "\n";
    std::cout << "volume_ratio  " << sc.volumeRatio << "\n";
    std::cout << "coverage      " << sc.coverage << "\n";
    std::cout << "outside       " << sc.outside << "\n";
    std::cout << "protrusion    " << c.protrusion << "   (largest, world units)\n";
    std::cout << "smallest_r    " << c.smallestRadius << "\n";
    std::cout << "mass_error    " << c.massError << "   (union of the spheres vs the grain)\n";
    std::cout << "centroid_error " << c.centroidError << "   (of the grain's bounding-box diagonal)\n";
    std::cout << "inertia_error " << c.inertiaError << "\n";
    if (const mss::ExactScore& e = c.exact; e.samples > 0) {
        std::cout << "dice_exact    " << e.dice << " +- " << e.diceError
                  << "   (Monte Carlo on the exact shapes: " << e.samples << " points, seed " << e.seed
                  << "; +- one standard error)\n";
        std::cout << "eta_exact     " << e.eta << " +- " << e.etaError << "\n";
        std::cout << "volume_exact  " << e.targetVolume << " +- " << e.targetVolumeError
                  << "   (the grain)\n";
        std::cout << "spheres_volume_exact " << e.sphereVolume << " +- " << e.sphereVolumeError << "\n";
    }
}

/// One table (text, and CSV with --csv) for several sphere files.
/// The table of several files; a file whose comparison failed (@p errors non-empty) is a row with its error.
void printTable(const std::vector<std::string>& files, const std::vector<mss::Comparison>& rows,
                const std::vector<std::string>& errors, const std::string& csv) {
    const bool exact =
        std::any_of(rows.begin(), rows.end(), [](const mss::Comparison& c) { return c.exact.samples > 0; });
    std::size_t w = 4;
    for (const std::string& f : files) w = std::max(w, f.size());
    w = std::min<std::size_t>(w, 48);
    std::cout << std::left << std::setw(int(w)) << "file" << std::right << std::setw(6) << "n" << std::setw(9)
              << "D" << std::setw(9) << "eta" << std::setw(9) << "vol" << std::setw(11) << "protr"
              << std::setw(10) << "r_min" << std::setw(11) << "mass" << std::setw(11) << "centroid"
              << std::setw(11) << "inertia" << (exact ? "   D_exact +- se" : "") << "\n";
    std::ostringstream out;
    out << std::setprecision(10)
        << "file,n,dice,eta,volume_ratio,protrusion,smallest_radius,mass_error,centroid_error,inertia_"
           "error,dice_exact,dice_exact_se,error\n";
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const mss::Comparison& c = rows[i];
        std::string name = files[i];
        if (name.size() > w) name = "..." + name.substr(name.size() - w + 3);
        if (!errors[i].empty()) { // one bad file is a row, not the end of the table
            std::cout << std::left << std::setw(int(w)) << name << "  error: " << errors[i] << "\n";
            std::string quoted;
            for (char ch : errors[i]) quoted += ch == '"' ? std::string("\"\"") : std::string(1, ch);
            out << '"' << files[i] << "\",,,,,,,,,,,,\"" << quoted << "\"\n";
            continue;
        }
        std::cout << std::left << std::setw(int(w)) << name << std::right << std::setw(6) << c.spheres
                  << std::fixed << std::setprecision(4) << std::setw(9) << c.score.dice << std::setw(9)
                  << c.score.eta << std::setw(9) << c.score.volumeRatio << std::defaultfloat
                  << std::setprecision(4) << std::setw(11) << c.protrusion << std::setw(10)
                  << c.smallestRadius << std::setw(11) << c.massError << std::setw(11) << c.centroidError
                  << std::setw(11) << c.inertiaError;
        if (c.exact.samples > 0)
            std::cout << std::fixed << std::setprecision(4) << std::setw(9) << c.exact.dice << " +- "
                      << std::setprecision(5) << c.exact.diceError << std::defaultfloat;
        std::cout << "\n";
        out << '"' << files[i] << "\"," << c.spheres << ',' << c.score.dice << ',' << c.score.eta << ','
            << c.score.volumeRatio << ',' << c.protrusion << ',' << c.smallestRadius << ',' << c.massError
            << ',' << c.centroidError << ',' << c.inertiaError << ',';
        if (c.exact.samples > 0)
            out << c.exact.dice << ',' << c.exact.diceError;
        else
            out << ',';
        out << ",\n";
    }
    std::cout << "D: Dice mismatch (eq. 27) on the scoring grid; vol: |spheres| / |grain|; protr: largest "
                 "protrusion (world units); mass, centroid, inertia: the union's errors against the grain"
              << (exact ? "; D_exact: on the exact shapes by Monte Carlo, +- one standard error" : "")
              << "\n";
    if (!csv.empty()) writeTextAtomically(csv, out.str());
}

int cmdCompare(const Args& a) {
    if (a.positional.size() < 2)
        throw std::invalid_argument("compare needs INPUT and at least one SPHERES file");
    const mss::Settings st = mss::settingsFrom(values(a, mss::command::Compare), mss::command::Compare);
    const mss::CompareOptions& o = st.compare;
    const std::string in = a.positional[0];
    const std::vector<std::string> files(a.positional.begin() + 1, a.positional.end());
    std::vector<std::string> inputs = files;
    inputs.push_back(in);
    if (a.has("csv")) mss::detail::refuseOverInputs("compare", {{"--csv", a.text("csv")}}, inputs);
    const bool voxels = isVoxelFile(in);
    if (!voxels) voxelOptionsOnly(a, in, {"voxelSize", "origin", "label"});
    const mss::VoxelGrid v = voxels ? readVoxels(st, in) : mss::VoxelGrid();
    const mss::TriangleMesh mesh = voxels ? mss::TriangleMesh() : readScaledMesh(st, in);
    // the grain's own faults first, named by the grain (a flat mesh): what fails below is the sphere file's
    if (!voxels) namingInput(in, [&] { return mss::meshMassProperties(mesh); });
    std::vector<mss::Comparison> rows;
    std::vector<std::string> errors;
    for (const std::string& f : files) {
        // the error names the file at fault (a sphere file in another frame), not the grain; but the grain's
        // voxelisation (a triangle soup over the memory limit) is the grain's, whatever file is scored
        auto one = [&] {
            const mss::SphereSet s = mss::readSpheres(f, st.clumpId);
            return namingInput(f, [&] {
                try {
                    return voxels ? mss::compareSpheres(v, s, o) : mss::compareSpheres(mesh, s, o);
                } catch (const std::invalid_argument& e) {
                    if (std::string(e.what()).rfind("voxelizeMesh:", 0) == 0)
                        throw std::invalid_argument(in + ": " + e.what() + " (the grain, not " + f + ")");
                    throw;
                }
            });
        };
        if (files.size() == 1) {
            rows.push_back(one());
            errors.emplace_back();
            continue;
        }
        try {
            rows.push_back(one());
            errors.emplace_back();
        } catch (const std::invalid_argument& e) {
            rows.emplace_back();
            errors.emplace_back(e.what());
        }
    }
    if (rows.size() == 1 && !a.has("csv"))
        printComparison(rows[0]);
    else
        printTable(files, rows, errors, a.has("csv") ? a.text("csv") : "");
    const auto failed =
        std::count_if(errors.begin(), errors.end(), [](const std::string& e) { return !e.empty(); });
    if (failed > 0) {
        std::cerr << "mss compare: " << failed << " of " << files.size()
                  << " files could not be compared (their rows "
                  << "say why)\n";
        return 1;
    }
    return 0;
}

int cmdInfo(const Args& a) {
    if (a.positional.size() != 1) throw std::invalid_argument("info needs one INPUT file");
    const std::string in = a.positional[0];
    const mss::Settings st = mss::settingsFrom(values(a, mss::command::Info), mss::command::Info);
    std::cout << std::setprecision(8);
    if (isVoxelFile(in)) {
        const mss::VoxelGrid v = readVoxels(st, in);
        std::cout << "voxels        " << v.nx() << " x " << v.ny() << " x " << v.nz() << "\n";
        std::cout << "solid         " << mss::countSolid(v) << "\n";
        std::cout << "voxel size    " << v.spec.h << "\n";
        std::cout << "volume        " << double(mss::countSolid(v)) * v.spec.h * v.spec.h * v.spec.h << "\n";
        return 0;
    }
    voxelOptionsOnly(a, in, {"voxelSize", "origin", "label"});
    const mss::TriangleMesh mesh = readScaledMesh(st, in);
    const mss::MeshInfo i = mss::analyzeMesh(mesh);
    std::cout << "vertices      " << i.vertices << "\n";
    std::cout << "triangles     " << i.triangles << "\n";
    std::cout << "closed        " << (i.closed ? "yes" : "no") << "\n";
    std::cout << "boundary_edges " << i.boundaryEdges << "\n";
    std::cout << "nonmanifold_edges " << i.nonManifoldEdges << "\n";
    std::cout << "inconsistent_edges " << i.inconsistentEdges << "\n";
    std::cout << "oriented      " << (i.consistentlyOriented ? "yes" : "no")
              << (i.signedVolume < 0 ? " (inside out)" : "") << "\n";
    std::cout << "degenerate    " << i.degenerateTriangles << "\n";
    try {
        // the count stops at its limit (within one triangle's pairs of it): past it, "at least"
        constexpr std::size_t kLimit = 1000000;
        const std::size_t n = mss::countSelfIntersections(mesh, kLimit);
        std::cout << "self_intersections " << (n >= kLimit ? "at least " : "") << n << "\n";
    } catch (const std::invalid_argument& e) { // the rest of the report still holds
        std::cout << "self_intersections not counted (" << e.what() << ")\n";
    }
    std::cout << "volume        " << std::abs(i.signedVolume) << "\n";
    std::cout << "bbox_min      " << i.lower.x() << " " << i.lower.y() << " " << i.lower.z() << "\n";
    std::cout << "bbox_max      " << i.upper.x() << " " << i.upper.y() << " " << i.upper.z() << "\n";
    return 0;
}

int cmdSurface(const Args& a) {
    if (a.positional.size() != 1) throw std::invalid_argument("surface needs one SPHERES file");
    const mss::Settings st = mss::settingsFrom(values(a, mss::command::Surface), mss::command::Surface);
    if (!a.has("output")) throw std::invalid_argument("surface needs -o MESH (.stl, .obj or .ply)");
    const std::string out = a.text("output");
    mss::detail::refuseOverInputs("surface", {{"-o", out}}, {a.positional[0]});
    const mss::FileFormat* f = mss::findFormat(out, mss::FileKind::Mesh);
    if (!f || !f->formatMesh) // before the work: the extension decides the writer
        throw std::invalid_argument(out + ": unknown mesh extension '" + mss::fileExtension(out) +
                                    "' (expected " + mss::formatList(mss::FileKind::Mesh, true) + ")");
    const mss::SphereSet s = mss::readSpheres(a.positional[0], st.clumpId);
    mss::SurfaceReport r;
    const mss::TriangleMesh mesh = mss::unionSurface(s, st.surface, &r);
    mss::writeMesh(mesh, out);
    std::cout << std::setprecision(8) << "wrote         " << out << "\n"
              << "spheres       " << s.size() << "\n"
              << "vertices      " << mesh.vertices.size() << "\n"
              << "triangles     " << mesh.triangles.size() << "\n"
              << "subdivisions  " << r.subdivisions << "\n"
              << "volume        " << r.volume << "\n"
              << "union_volume  " << r.unionVolume << "  (exact)\n"
              << "volume_error  " << (r.volume / r.unionVolume - 1.0) << "\n"
              << "longest_edge  " << r.longestEdge << "\n"
              << "smallest_angle " << r.smallestAngle << " degrees\n";
    return 0;
}

// ---- the command line (CLI11): subcommands, per-subcommand help; values are kept as text and converted by
// the helpers above, so that every bad value gets the same message as before

/// "unknown option '--sphere': did you mean '--spheres'?" for what CLI11 did not expect.
std::string unknownOption(const CLI::App* sub, const std::vector<std::string>& extras) {
    const std::string bad = extras.empty() ? "" : extras.front();
    std::string best;
    std::size_t bestD = 4; // suggest only what is close
    for (const CLI::Option* o : sub->get_options())
        for (const std::string& name : o->get_lnames()) {
            const std::string cand = "--" + name;
            const std::size_t d = mss::editDistance(bad, cand);
            if (d < bestD || (bad.size() > 2 && cand.rfind(bad, 0) == 0 && d < bestD + 4)) {
                bestD = std::min(d, bestD);
                best = cand;
            }
        }
    if (bad.empty() || bad[0] != '-') return "unexpected argument '" + bad + "'";
    return "unknown option '" + bad + "'" + (best.empty() ? "" : ": did you mean '" + best + "'?");
}

/// The --help line of a table row: its help, unit, range and default.
std::string helpOf(const mss::OptionSpec& s) {
    std::string extra;
    auto add = [&extra](const std::string& t) { extra += (extra.empty() ? "" : "; ") + t; };
    if (*s.unit) add(s.unit);
    if (s.type == mss::OptionType::Choice) add(std::string("one of ") + s.choices);
    const std::string range = mss::optionRange(s);
    if (!range.empty()) add(range);
    if (*s.fallback && s.type != mss::OptionType::Flag) add(std::string("default ") + s.fallback);
    const bool offFlag = s.type == mss::OptionType::Flag && std::string(s.fallback) == "true";
    return (offFlag ? "turns off: " : "") + std::string(s.help) + (extra.empty() ? "" : " [" + extra + "]");
}

/// The options of command @p cmd, from the option table: values kept as text by name, parsed by values().
void tableOptions(CLI::App* sub, Args& a, unsigned cmd) {
    for (const mss::OptionSpec& s : mss::optionTable()) {
        if (!(s.commands & cmd) || !*s.flag) continue;
        const std::string name = s.name;
        if (s.type == mss::OptionType::Flag) {
            const std::string set = std::string(s.fallback) == "true" ? "false" : "true";
            sub->add_flag_callback(
                s.flag, [&a, name, set] { a.opts[name] = set; }, helpOf(s));
        } else if (s.type == mss::OptionType::Planes) {
            sub->add_option("--plane", a.planes, helpOf(s))
                ->type_name(s.metavar)
                ->type_size(1)
                ->expected(1)
                ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
        } else {
            sub->add_option_function<std::string>(
                   s.flag, [&a, name](const std::string& v) { a.opts[name] = v; }, helpOf(s))
                ->type_name(s.metavar);
        }
    }
    if (cmd & (mss::command::Generate | mss::command::Compare | mss::command::Info)) {
        // the name before --voxel-size took the voxel volumes' edge too: still read, not shown
        sub->add_option_function<std::string>(
               "--npy-voxel-size",
               [&a](const std::string& v) {
                   std::cerr << "mss: warning: --npy-voxel-size is now --voxel-size\n";
                   a.opts["voxelSize"] = v;
               },
               "")
            ->group("");
    }
}

void inputArgument(CLI::App* sub, Args& a) {
    sub->add_option_function<std::string>(
           "INPUT", [&a](const std::string& v) { a.positional.push_back(v); }, "mesh or voxel file")
        ->required();
}

CLI::App* generateCommand(CLI::App& app, Args& a) {
    CLI::App* g = app.add_subcommand("generate", "spheres for a mesh (.stl .obj .off .ply) or voxels (.npy)");
    g->footer("Termination (paper section 3.5): give at least one of --spheres, --eta, --dice, --rmin.");
    inputArgument(g, a);
    tableOptions(g, a, mss::command::Generate);
    return g;
}

CLI::App* compareCommand(CLI::App& app, Args& a) {
    CLI::App* c =
        app.add_subcommand("compare", "score a sphere file against the target on a grid of its own");
    inputArgument(c, a);
    c->add_option_function<std::vector<std::string>>(
         "SPHERES",
         [&a](const std::vector<std::string>& v) {
             a.positional.insert(a.positional.end(), v.begin(), v.end());
         },
         "sphere files (.csv, .txt, CLUMP's and YADE's, legacy VTK); several give one table")
        ->required();
    tableOptions(c, a, mss::command::Compare);
    return c;
}

CLI::App* infoCommand(CLI::App& app, Args& a) {
    CLI::App* i = app.add_subcommand("info", "what was read: mesh closedness, defects, volume; voxel counts");
    inputArgument(i, a);
    tableOptions(i, a, mss::command::Info);
    return i;
}

CLI::App* surfaceCommand(CLI::App& app, Args& a) {
    CLI::App* c =
        app.add_subcommand("surface", "the boundary of the spheres' union as a closed triangle mesh: mss "
                                      "surface SPHERES -o clump.stl|.obj|.ply");
    c->add_option_function<std::string>(
         "SPHERES", [&a](const std::string& v) { a.positional.push_back(v); },
         "a sphere file (.csv, .txt, .vtk, or a template of mss export)")
        ->required();
    tableOptions(c, a, mss::command::Surface);
    return c;
}

/// The cores this run may use (its affinity mask, as OpenMP counts them), the threads it will start
/// (--threads T if given, else one per core; 0 when not given) and the cores nobody else is running on now
/// (mss::othersRunning: the least of five looks, as a shell starting the rest of a pipeline runs for a
/// moment).
struct CoreUse {
    long cores = 1, threadsAsked = 0, free = 0;
    bool known = false; ///< whether /proc/stat told the processes running
};
CoreUse coreUse(int argc, char** argv) {
    CoreUse u;
    u.cores = mss::usableCores();
    for (int k = 1; k < argc; ++k) {
        const std::string w = argv[k];
        if (w == "--threads" && k + 1 < argc) u.threadsAsked = std::atol(argv[k + 1]);
        if (w.rfind("--threads=", 0) == 0) u.threadsAsked = std::atol(w.c_str() + 10);
    }
    const long others = mss::othersRunning();
    u.known = others >= 0;
    u.free = u.known ? u.cores - others : 0; // fewer than none when more run than there are cores
    return u;
}

/// Whether subcommand @p command runs in this process (the others run in python3).
bool runsHere(const std::string& command) {
    return command == "generate" || command == "compare" || command == "info" || command == "surface";
}

/// Set for the run of this program: the threads to pin to cores of their own.
constexpr const char* kSpread = "MSS_SPREAD_THREADS";

/// OpenMP's waiting and thread count for this run, through the environment that libgomp reads when it
/// starts, unless the user chose (OMP_WAIT_POLICY). @return whether it set them.
/// Spinning OpenMP threads collapse when the cores are shared: femur 70 spheres, 2 threads, 3 busy
/// processes on 2 cores: 2-3x as long as on 1 thread, and 3x as long as with passive waiting
/// (bench/load.sh). But passive waiting wakes each thread through the kernel at every parallel region, and
/// refinement runs thousands of short ones: idle, 2 passive threads took as long as one thread, and
/// threads that spin 10000 rounds before they sleep about a quarter less. So a short spin
/// (OMP_WAIT_POLICY=ACTIVE, GOMP_SPINCOUNT=10000) when every thread finds a free core now, else
/// OMP_WAIT_POLICY=PASSIVE. Without --threads (and OMP_NUM_THREADS), a run on busy cores also starts only as
/// many threads as cores are free, at least one: 2 passive threads among 3 busy processes on 2 cores took up
/// to 1.7x as long as one (results do not depend on the thread count).
bool chooseOpenMp(int argc, char** argv) {
    if (std::getenv("OMP_WAIT_POLICY") || argc < 1) return false;
    const CoreUse u = coreUse(argc, argv);
    const long threads = u.threadsAsked > 0 ? u.threadsAsked : u.cores;
    if (threads <= u.free) {
        setenv("OMP_WAIT_POLICY", "ACTIVE", 1);
        setenv("GOMP_SPINCOUNT", "10000", 0);
        // the threads are not pinned to cores of their own (mss::spreadThreads, MSS_SPREAD_THREADS=N asks for
        // it): pinned, an idle machine's default run took one thread's time (femur 70: 0.18-0.23 s against
        // 0.14-0.16 s unpinned, --threads 2 0.13-0.16 s; bench/threads.sh)
    } else {
        setenv("OMP_WAIT_POLICY", "PASSIVE", 1);
        if (u.known && u.threadsAsked <= 0 && !std::getenv("OMP_NUM_THREADS"))
            setenv("OMP_NUM_THREADS", std::to_string(std::max(1L, u.free)).c_str(), 1);
    }
    return true;
}

// malloc's settings: its own blocks on transparent huge pages too, and blocks under 32 MB from its heap,
// kept for reuse: a fresh 4 KiB page costs a fault under a virtual machine's kernel (building the
// ellipsoid's mesh hierarchy about 2x faster so). The heap grows 8 MB at a time (top_pad): grown by the
// default 128 KiB, its new pages seldom made a whole 2 MiB range of the mapping, and took 4 KiB pages (a
// third fewer faults a run so). The large arrays are on huge pages in the library (BigAllocator).
constexpr std::size_t kMmapThreshold = std::size_t(32) << 20, kTrimThreshold = std::size_t(256) << 20,
                      kTopPad = std::size_t(8) << 20;

#if MSS_EARLY_ENV
/// Linked statically (CMakeLists.txt), libgomp reads its environment in a constructor of default priority,
/// after this one: the settings are made here, in this process (running itself again with them, as the
/// dynamically linked build does, cost a few per cent of a small run). malloc's three through mallopt();
/// glibc reads GLIBC_TUNABLES before any code of ours runs, so the huge pages of glibc.malloc.hugetlb=1 are
/// given to the heap's first 16 MB here, grown and marked at once (femur and ellipsoid runs fit in them;
/// beyond, the heap grows on small pages). A malloc tunable the user set is left as set. Unlike the dynamic
/// build, the malloc settings are made also where the user chose OpenMP's waiting (that build then does not
/// run itself again).
__attribute__((constructor(101))) void earlySettings(int argc, char** argv, char**) {
    chooseOpenMp(argc, argv);
    // as the dynamic build's GLIBC_TUNABLES: each setting unless the user gave that tunable
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    auto given = [tunables](const char* name) { return tunables && std::strstr(tunables, name); };
    if (!given("glibc.malloc.mmap_threshold=")) mallopt(M_MMAP_THRESHOLD, int(kMmapThreshold));
    if (!given("glibc.malloc.trim_threshold=")) mallopt(M_TRIM_THRESHOLD, int(kTrimThreshold));
    if (!given("glibc.malloc.top_pad=")) mallopt(M_TOP_PAD, int(kTopPad));
    if (given("glibc.malloc.hugetlb=")) return;
    auto* before = static_cast<char*>(sbrk(0));
    static void* volatile block;  // volatile: the compiler may not drop a malloc() whose block is unused
    block = std::malloc(kTopPad); // more than the heap holds yet: it grows by this and top_pad
    auto* after = static_cast<char*>(sbrk(0));
    constexpr std::uintptr_t kPage = 4096;
    auto* from =
        reinterpret_cast<char*>((reinterpret_cast<std::uintptr_t>(before) + kPage - 1) & ~(kPage - 1));
    if (before != reinterpret_cast<char*>(-1) && after > from)
        madvise(from, std::size_t(after - from), MADV_HUGEPAGE);
    std::free(block); // back to the heap's top (under the trim threshold: kept)
}
#endif

} // namespace

int main(int argc, char** argv) {
#if !MSS_EARLY_ENV
    // libgomp and glibc read their settings when the program starts: it runs itself again with them
    if (chooseOpenMp(argc, argv)) {
        const char* tunables = std::getenv("GLIBC_TUNABLES");
        std::string t = tunables ? tunables : "";
        for (const std::string& tunable : {std::string("glibc.malloc.hugetlb=1"),
                                           "glibc.malloc.mmap_threshold=" + std::to_string(kMmapThreshold),
                                           "glibc.malloc.trim_threshold=" + std::to_string(kTrimThreshold),
                                           "glibc.malloc.top_pad=" + std::to_string(kTopPad)}) {
            const std::string name = tunable.substr(0, tunable.find('=') + 1);
            if (t.find(name) == std::string::npos) t += (t.empty() ? "" : ":") + tunable;
        }
        setenv("GLIBC_TUNABLES", t.c_str(), 1);
        execv("/proc/self/exe", argv); // returns only on failure: then go on as we are
    }
#endif
    if (const char* spread = std::getenv(kSpread)) { // set by chooseOpenMp()
        const int threads = std::atoi(spread);
        unsetenv(kSpread);
        // only where the work runs here (the others run python3, which starts its own processes)
        const std::string command = argc > 1 ? argv[1] : "";
        if (threads > 1 && runsHere(command) &&
            sched_getaffinity(0, sizeof(cpu_set_t), &unpinned().mask) == 0) {
            unpinned().pinned = true; // (where only some threads could be pinned too)
            mss::spreadThreads(threads);
        }
    }
    CLI::App app{"mss: multi-sphere shape generator (MSS) for DEM clumps"};
    app.require_subcommand(1, 1);
    app.set_version_flag("--version", std::string("mss (yade-mss) ") + mss::version());
    Args a;
    CLI::App* gen = generateCommand(app, a);
    CLI::App* cmp = compareCommand(app, a);
    CLI::App* inf = infoCommand(app, a);
    CLI::App* sur = surfaceCommand(app, a);
    app.add_subcommand("preview",
                       "draw a clump against its grain (PNG): mss preview GRAIN SPHERES -o OUT.png");
    app.add_subcommand(
        "curve", "D and time against the sphere count (PNG, CSV): mss curve GRAIN --counts A:B -o OUT.png");
    app.add_subcommand("ochart",
                       "D, simulation cost n / r_min and O = cost x D over sphere counts and radius "
                       "bounds (PNG, CSV): mss ochart GRAIN -o OUT.png [--dice X --min-cost]");
    app.add_subcommand("export", "a clump as another DEM code's template, with the grain's exact mass "
                                 "properties: mss export GRAIN|RESULT.npz --format liggghts -o OUT");
    app.add_subcommand(
        "batch", "a labelled CT volume or a folder of grains to a DEM assembly: mss batch INPUT... -o DIR");
    app.add_subcommand("spheropolygon",
                       "2-D particle images to spheropolygons: mss spheropolygon IMAGE -o OUT.json");
    app.add_subcommand("triaxial", "a triaxial test of the grains' clumps in YADE, at one or several sphere "
                                   "counts: mss triaxial GRAIN|DIR -o DIR --spheres 5,10,20");
    const std::string first = argc > 1 ? argv[1] : "";
    // these run in python3 (matplotlib, Dask): their options and help are there
    if (first == "preview" || first == "curve" || first == "ochart" || first == "batch" ||
        first == "spheropolygon" || first == "export" || first == "triaxial") {
        try {
            return runPython(std::vector<std::string>(argv + 1, argv + argc));
        } catch (const std::exception& e) {
            std::cerr << "mss " << first << ": error: " << e.what() << "\n";
            return 1;
        }
    }
    if (!first.empty() && first[0] != '-' && !runsHere(first)) {
        std::cerr << "mss: unknown command '" << argv[1]
                  << "' (generate, compare, info, surface, preview, curve, ochart, export, batch, "
                     "spheropolygon or triaxial; mss --help)\n";
        return 2;
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ExtrasError& e) {
        CLI::App* sub = gen->parsed()   ? gen
                        : cmp->parsed() ? cmp
                        : inf->parsed() ? inf
                        : sur->parsed() ? sur
                                        : &app;
        std::vector<std::string> extras = sub->remaining();
        std::cerr << "mss " << sub->get_name() << ": error: " << unknownOption(sub, extras) << "\n"
                  << "run 'mss " << sub->get_name() << " --help' for the options\n";
        return 2;
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);
        std::cerr << "mss: error: " << e.what() << "\nrun 'mss --help' or 'mss COMMAND --help'\n";
        return 2;
    }
    const std::string cmd = gen->parsed()   ? "generate"
                            : cmp->parsed() ? "compare"
                            : sur->parsed() ? "surface"
                                            : "info";
    std::signal(SIGINT, onInterrupt);
    mss::showProgressOnStandardError();
    try {
        if (cmd == "generate") return cmdGenerate(a);
        if (cmd == "compare") return cmdCompare(a);
        if (cmd == "surface") return cmdSurface(a);
        return cmdInfo(a);
    } catch (const std::bad_alloc&) { // --memory-limit allows more than this machine could give
        std::cerr
            << "mss " << cmd
            << ": error: out of memory: the machine could not give what this run needs; lower --resolution, "
               "or set --memory-limit to the memory the machine has (default 8 GiB) to be told before\n";
        return 1;
    } catch (const mss::OptionError& e) { // named as the command line spells it
        std::cerr << "mss " << cmd << ": error: " << flagOf(e.option()) << e.detail() << "\n";
        return 1;
    } catch (const mss::Interrupted&) {
        std::cerr << "\nmss " << cmd << ": interrupted (Ctrl-C): nothing was written\n";
        return 130;
    } catch (const std::exception& e) {
        std::cerr << "mss " << cmd << ": error: " << spelled(e.what()) << "\n";
        return 1;
    }
}
