// Boost.Python module _mss: the yade-mss core for Python (YADE's module-pair style; the facade is yade_mss).
//
// Only built-in Python types cross this boundary (lists of floats, bytes, dicts, tuples): no converter is
// registered for Eigen or any other type, so loading this module inside YADE cannot replace YADE's own
// converters (registering an Eigen converter again would silently change Facet.vertices and friends for the
// whole process). The facade turns lists into numpy arrays.
#include "mss.hpp"

#include <boost/python.hpp>
#ifdef _OPENMP
#include <omp.h>
#endif

#include <cstdint>
#include <cstring>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

namespace py = boost::python;

namespace {

/// The values of @p o as doubles when it is a C-contiguous buffer of native float64, float32, int32 or int64
/// (a numpy array); false otherwise (a list, bytes, another layout or type), and @p out is left empty.
/// Converting a mesh's 40k numbers one Python object at a time took 4-5 ms, several times per split.
bool fromBuffer(const py::object& o, std::vector<double>& out) {
    if (!PyObject_CheckBuffer(o.ptr()) || PyBytes_Check(o.ptr()) || PyByteArray_Check(o.ptr())) return false;
    Py_buffer b;
    if (PyObject_GetBuffer(o.ptr(), &b, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) != 0) {
        PyErr_Clear();
        return false;
    }
    struct Release {
        Py_buffer* b;
        ~Release() { PyBuffer_Release(b); }
    } release{&b};
    std::string f = b.format ? b.format : "B";
    if (!f.empty() && (f[0] == '<' || f[0] == '=' || f[0] == '@')) f = f.substr(1); // native order here
    const std::size_t n = b.itemsize > 0 ? std::size_t(b.len / b.itemsize) : 0;
    out.resize(n);
    const char* p = static_cast<const char*>(b.buf);
    auto copy = [&](auto type) {
        using T = decltype(type);
        if (b.itemsize != Py_ssize_t(sizeof(T))) return false;
        for (std::size_t i = 0; i < n; ++i) {
            T v;
            std::memcpy(&v, p + i * sizeof(T), sizeof(T));
            out[i] = static_cast<double>(v);
        }
        return true;
    };
    const bool done = f == "d"                 ? copy(double())
                      : f == "f"               ? copy(float())
                      : f == "i"               ? copy(std::int32_t())
                      : (f == "l" || f == "q") ? copy(std::int64_t())
                                               : false;
    if (!done) out.clear(); // another type (bool, unsigned, big endian, ...): element by element, as before
    return done;
}

std::vector<double> doubles(const py::object& o, const char* what) {
    std::vector<double> out;
    if (fromBuffer(o, out)) return out;
    if (PyObject_CheckBuffer(o.ptr()) && PyObject_HasAttrString(o.ptr(), "tolist")) {
        const py::object l =
            o.attr("tolist")(); // an array of another layout or type: its numbers as Python's
        if (PyList_Check(l.ptr())) return doubles(l, what);
    }
    const long n = py::len(o);
    out.reserve(static_cast<std::size_t>(n));
    for (long i = 0; i < n; ++i) {
        py::extract<double> x(o[i]);
        if (!x.check())
            throw std::invalid_argument(std::string(what) + ": element " + std::to_string(i) +
                                        " is not a number");
        out.push_back(x());
    }
    return out;
}

std::vector<mss::Vec3> points(const py::object& o, const char* what) {
    const std::vector<double> flat = doubles(o, what);
    if (flat.size() % 3)
        throw std::invalid_argument(std::string(what) + ": expected a flat list of x, y, z triples");
    std::vector<mss::Vec3> out(flat.size() / 3);
    for (std::size_t i = 0; i < out.size(); ++i)
        out[i] = mss::Vec3(flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]);
    return out;
}

mss::Vec3 vec3(const py::object& o, const char* what) {
    const std::vector<double> v = doubles(o, what);
    if (v.size() != 3) throw std::invalid_argument(std::string(what) + ": expected 3 numbers");
    return mss::Vec3(v[0], v[1], v[2]);
}

py::list list(const mss::Vec3& v) {
    py::list l;
    for (int a = 0; a < 3; ++a) l.append(v[a]);
    return l;
}

mss::TriangleMesh mesh(const py::object& vertices, const py::object& triangles) {
    mss::TriangleMesh m;
    m.vertices = points(vertices, "mesh vertices");
    const std::vector<double> t = doubles(triangles, "mesh triangles");
    if (t.size() % 3) throw std::invalid_argument("mesh triangles: expected a flat list of index triples");
    for (std::size_t i = 0; i < t.size(); i += 3) {
        std::array<int, 3> tri{};
        for (int c = 0; c < 3; ++c) {
            if (t[i + c] != static_cast<double>(static_cast<int>(t[i + c])))
                throw std::invalid_argument("mesh triangles: indices must be integers");
            tri[c] = static_cast<int>(t[i + c]);
        }
        m.triangles.push_back(tri);
    }
    mss::validateMesh(m, "mesh");
    return m;
}

mss::SphereSet spheres(const py::object& centers, const py::object& radii) {
    mss::SphereSet s;
    s.centers = points(centers, "sphere centres");
    s.radii = doubles(radii, "sphere radii");
    mss::validateSpheres(s, "spheres");
    return s;
}

/// A grid of @p shape, voxel edge and origin, and the bytes of its voxels (@p width each), all checked.
mss::GridSpec gridOf(const py::object& data, const py::object& shape, double voxelSize,
                     const py::object& origin, std::size_t width, const char* where, const char** bytes) {
    const std::string w = where;
    if (py::len(shape) != 3) throw std::invalid_argument(w + ": the array must be 3-D");
    mss::GridSpec g;
    std::array<long long, 3> dims{};
    for (int a = 0; a < 3; ++a) dims[a] = py::extract<long long>(shape[a]);
    mss::checkGridSize(where, dims, 1, std::size_t(1) << 40);
    for (int a = 0; a < 3; ++a) g.dims[a] = static_cast<int>(dims[a]);
    if (!(voxelSize > 0.0) || !std::isfinite(voxelSize))
        throw std::invalid_argument(w + ": voxel size must be > 0 and finite, got " +
                                    std::to_string(voxelSize));
    g.h = voxelSize;
    g.origin = vec3(origin, (w + ": origin").c_str());
    if (!g.origin.allFinite()) throw std::invalid_argument(w + ": origin is not finite");
    char* buf = nullptr;
    Py_ssize_t len = 0;
    if (!PyBytes_Check(data.ptr()) || PyBytes_AsStringAndSize(data.ptr(), &buf, &len) != 0)
        throw std::invalid_argument(w + ": data must be bytes");
    if (static_cast<std::size_t>(len) != g.size() * width)
        throw std::invalid_argument(w + ": " + std::to_string(len) + " bytes for " +
                                    std::to_string(g.size()) + " voxels of " + std::to_string(width));
    *bytes = buf;
    return g;
}

/// Voxels from bytes with x fastest (numpy Fortran order), one byte per voxel, non-zero = solid.
mss::VoxelGrid voxels(const py::object& data, const py::object& shape, double voxelSize,
                      const py::object& origin) {
    const char* buf = nullptr;
    const mss::GridSpec g = gridOf(data, shape, voxelSize, origin, 1, "voxels", &buf);
    mss::VoxelGrid v(g, 0);
    for (std::size_t q = 0; q < g.size(); ++q) v.data[q] = buf[q] != 0;
    return v;
}

std::vector<mss::Plane> planes(const py::object& list) {
    std::vector<mss::Plane> out;
    for (long i = 0; i < py::len(list); ++i) {
        const std::vector<double> v = doubles(list[i], "planes");
        if (v.size() != 6) throw std::invalid_argument("generate: a plane is 6 numbers: point and normal");
        mss::Plane p;
        p.point = mss::Vec3(v[0], v[1], v[2]);
        p.normal = mss::Vec3(v[3], v[4], v[5]);
        out.push_back(p);
    }
    return out;
}

/// A Python value as the option table's row @p spec types it (the facade has checked its kind: this only
/// converts). @throws mss::OptionError
mss::OptionValue optionValue(const mss::OptionSpec& spec, const py::object& v) {
    using T = mss::OptionType;
    const auto bad = [&](const char* what) { return mss::OptionError("options", spec.name, what); };
    switch (spec.type) {
    case T::Integer: {
        if (PyBool_Check(v.ptr()) || !PyLong_Check(v.ptr())) throw bad(" must be an integer");
        int overflow = 0;
        const long long x = PyLong_AsLongLongAndOverflow(v.ptr(), &overflow);
        if (overflow) throw bad(" is out of range");
        return x;
    }
    case T::Number: {
        py::extract<double> x(v);
        if (PyBool_Check(v.ptr()) || !x.check()) throw bad(" must be a number");
        return x();
    }
    case T::Flag:
        if (!PyBool_Check(v.ptr())) throw bad(" must be True or False");
        return v.ptr() == Py_True;
    case T::Choice:
    case T::Text: {
        py::extract<std::string> x(v);
        if (!x.check()) throw bad(" must be a string");
        return x();
    }
    case T::Point:
        return vec3(v, spec.name);
    case T::Point2: {
        const std::vector<double> xy = doubles(v, spec.name);
        if (xy.size() != 2) throw bad(" must be 2 numbers");
        return mss::Vec3(xy[0], xy[1], 0.0);
    }
    case T::Planes:
        return planes(v);
    case T::Files: {
        std::vector<std::string> out;
        for (long i = 0; i < py::len(v); ++i) {
            py::extract<std::string> f(v[i]);
            if (!f.check()) throw bad(" must be a list of file names");
            out.push_back(f());
        }
        return out;
    }
    }
    throw bad(" has a type the table does not know");
}

/// Settings of command @p cmd from a dict of keyword -> value: a key the command does not take is an error.
mss::Settings settings(const py::dict& d, unsigned cmd) {
    mss::OptionValues values;
    const py::list keys = d.keys();
    for (long i = 0; i < py::len(keys); ++i) {
        py::extract<std::string> key(keys[i]);
        if (!key.check()) throw std::invalid_argument("options: the keys must be option names");
        const mss::OptionSpec* spec = mss::findOption(key(), cmd);
        if (spec)
            values[key()] = optionValue(*spec, d[keys[i]]);
        else
            values[key()] = false; // settingsFrom names it and suggests the nearest
    }
    return mss::settingsFrom(values, cmd);
}

const char* typeWord(mss::OptionType t) {
    switch (t) {
    case mss::OptionType::Integer:
        return "int";
    case mss::OptionType::Number:
        return "float";
    case mss::OptionType::Flag:
        return "bool";
    case mss::OptionType::Choice:
        return "choice";
    case mss::OptionType::Text:
        return "str";
    case mss::OptionType::Point:
        return "point";
    case mss::OptionType::Point2:
        return "point2";
    case mss::OptionType::Planes:
        return "planes";
    case mss::OptionType::Files:
        return "files";
    }
    return "";
}

unsigned commandBit(const std::string& name) {
    static const std::pair<const char*, unsigned> kCommands[] = {
        {"generate", mss::command::Generate}, {"compare", mss::command::Compare},
        {"info", mss::command::Info},         {"batch", mss::command::Batch},
        {"preview", mss::command::Preview},   {"curve", mss::command::Curve},
        {"ochart", mss::command::Ochart},     {"spheropolygon", mss::command::Spheropolygon},
        {"export", mss::command::Export},     {"surface", mss::command::Surface},
        {"triaxial", mss::command::Triaxial}};
    for (const auto& [word, bit] : kCommands)
        if (name == word) return bit;
    throw std::invalid_argument("options: no command '" + name + "'");
}

/// The value of @p text for option @p name of @p command, parsed as the command line parses it.
py::object parseOption(const std::string& name, const std::string& command, const std::string& text) {
    const mss::OptionSpec* spec = mss::findOption(name, commandBit(command));
    if (!spec) throw std::invalid_argument(command + ": no option '" + name + "'");
    const mss::OptionValue v = mss::parseOption(*spec, text);
    if (const bool* b = std::get_if<bool>(&v)) return py::object(*b);
    if (const long long* i = std::get_if<long long>(&v)) return py::object(*i);
    if (const double* x = std::get_if<double>(&v)) return py::object(*x);
    if (const std::string* t = std::get_if<std::string>(&v)) return py::object(*t);
    if (const mss::Vec3* p = std::get_if<mss::Vec3>(&v))
        return spec->type == mss::OptionType::Point2 ? py::make_tuple(p->x(), p->y())
                                                     : py::make_tuple(p->x(), p->y(), p->z());
    if (const auto* ps = std::get_if<std::vector<mss::Plane>>(&v)) {
        py::list out;
        for (const mss::Plane& q : *ps)
            out.append(py::make_tuple(py::make_tuple(q.point.x(), q.point.y(), q.point.z()),
                                      py::make_tuple(q.normal.x(), q.normal.y(), q.normal.z())));
        return out;
    }
    py::list files;
    for (const std::string& f : std::get<std::vector<std::string>>(v)) files.append(f);
    return files;
}

/// The format table (mss/io.hpp) as a list of dicts: extension, kind, description, read (by the core),
/// written.
py::list fileFormats() {
    py::list out;
    for (const mss::FileFormat& f : mss::fileFormats()) {
        py::dict d;
        d["extension"] = f.extension;
        d["kind"] = f.kind == mss::FileKind::Mesh     ? "mesh"
                    : f.kind == mss::FileKind::Voxels ? "voxels"
                                                      : "spheres";
        d["description"] = f.description;
        d["readByCore"] = f.readByCore;
        d["written"] = f.formatSpheres != nullptr;  // spheres written (generate -o)
        d["meshWritten"] = f.formatMesh != nullptr; // a mesh written (surface -o)
        out.append(d);
    }
    return out;
}

/// The option table (mss/options.hpp) as a list of dicts, for the facade's parsers and docstrings.
py::list optionTable() {
    static const std::pair<unsigned, const char*> kCommands[] = {
        {mss::command::Generate, "generate"}, {mss::command::Compare, "compare"},
        {mss::command::Info, "info"},         {mss::command::Batch, "batch"},
        {mss::command::Preview, "preview"},   {mss::command::Curve, "curve"},
        {mss::command::Ochart, "ochart"},     {mss::command::Spheropolygon, "spheropolygon"},
        {mss::command::Export, "export"},     {mss::command::Surface, "surface"},
        {mss::command::Triaxial, "triaxial"}};
    py::list out;
    for (const mss::OptionSpec& s : mss::optionTable()) {
        py::dict d;
        d["name"] = s.name;
        d["flag"] = s.flag;
        d["python"] = s.python;
        d["type"] = typeWord(s.type);
        d["default"] = s.fallback;
        d["low"] = s.low;
        d["high"] = s.high;
        d["lowOpen"] = s.lowOpen;
        d["highOpen"] = s.highOpen;
        d["range"] = mss::optionRange(s);
        d["choices"] = s.choices;
        d["unit"] = s.unit;
        d["metavar"] = s.metavar;
        d["help"] = s.help;
        py::list commands;
        for (const auto& [bit, name] : kCommands)
            if (s.commands & bit) commands.append(name);
        d["commands"] = commands;
        out.append(d);
    }
    return out;
}

py::dict grid(const mss::GridSpec& g) {
    py::dict d;
    d["dims"] = py::make_tuple(g.dims[0], g.dims[1], g.dims[2]);
    d["voxelSize"] = g.h;
    d["origin"] = list(g.origin);
    return d;
}

py::dict result(const mss::Result& r) {
    py::dict d;
    py::list c, rad;
    for (std::size_t i = 0; i < r.spheres.size(); ++i) {
        for (int a = 0; a < 3; ++a) c.append(r.spheres.centers[i][a]);
        rad.append(r.spheres.radii[i]);
    }
    d["centers"] = c;
    d["radii"] = rad;
    const mss::Metrics& m = r.metrics;
    py::dict md;
    md["spheres"] = m.spheres;
    md["eta"] = m.eta;
    md["dice"] = m.dice;
    md["iterations"] = m.iterations;
    md["solidVoxels"] = m.solidVoxels;
    md["sphereVoxels"] = m.sphereVoxels;
    md["symmetryPlanes"] = m.symmetryPlanes;
    md["clipped"] = m.clipped;
    md["protrusion"] = m.protrusion;
    md["protrusionLimit"] = m.protrusionLimit;
    md["smallestRadius"] = m.smallestRadius;
    md["inscribedRadius"] = m.inscribedRadius;
    md["contacts"] = m.contacts;
    md["contactsAdded"] = m.contactsAdded;
    md["contactsMissed"] = m.contactsMissed;
    py::list warnings;
    for (const std::string& w : m.warnings) warnings.append(w);
    md["warnings"] = warnings;
    md["secondsVoxelize"] = m.secondsVoxelize;
    md["secondsEdt"] = m.secondsEdt;
    md["secondsSelect"] = m.secondsSelect;
    md["secondsRefine"] = m.secondsRefine;
    md["secondsTotal"] = m.secondsTotal;
    d["metrics"] = md;
    d["grid"] = grid(r.grid);
    return d;
}

py::dict mass(const mss::MassProperties& m) {
    py::dict d;
    d["volume"] = m.volume;
    d["centroid"] = list(m.centroid);
    py::list I;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) I.append(m.inertia(i, j));
    d["inertia"] = I;
    return d;
}

py::dict score(const mss::Score& s) {
    py::dict d;
    d["dice"] = s.dice;
    d["eta"] = s.eta;
    d["volumeRatio"] = s.volumeRatio;
    d["coverage"] = s.coverage;
    d["outside"] = s.outside;
    d["targetVoxels"] = s.targetVoxels;
    d["sphereVoxels"] = s.sphereVoxels;
    d["grid"] = grid(s.grid);
    return d;
}

// ---- the module's functions ----

py::tuple readMesh(const std::string& path) {
    const mss::TriangleMesh m = mss::readMesh(path);
    py::list v, t;
    for (const auto& p : m.vertices)
        for (int a = 0; a < 3; ++a) v.append(p[a]);
    for (const auto& tri : m.triangles)
        for (int c : tri) t.append(c);
    return py::make_tuple(v, t);
}

/// A voxel grid's data as Python bytes (x fastest, one byte per voxel) and its shape.
py::object voxelBytes(const mss::VoxelGrid& v) {
    return py::object(py::handle<>(
        PyBytes_FromStringAndSize(reinterpret_cast<const char*>(v.data.data()), Py_ssize_t(v.data.size()))));
}
py::tuple shape(const mss::VoxelGrid& v) {
    return py::make_tuple(v.nx(), v.ny(), v.nz());
}

/// .npy file -> (bytes, x fastest, one per voxel: 1 solid), shape); the C++ reader's checks and messages.
py::tuple readNpy(const std::string& path, long long label) {
    const mss::VoxelGrid v = mss::readNpy(path, 1.0, mss::Vec3::Zero(), label);
    return py::make_tuple(voxelBytes(v), shape(v));
}

/// A mesh voxelised (voxel centres inside, section 2.2) on a grid of @p resolution voxels along its shortest
/// edge: (bytes x fastest, dims, voxel size, origin), as readNpy gives them.
py::tuple voxelizeMesh(const py::object& vertices, const py::object& triangles, int resolution) {
    mss::Resolution r;
    r.resolution = resolution;
    const mss::VoxelGrid v = mss::voxelizeMesh(mesh(vertices, triangles), r);
    return py::make_tuple(voxelBytes(v), shape(v), v.spec.h, list(v.spec.origin));
}

py::dict meshInfo(const py::object& vertices, const py::object& triangles) {
    const mss::MeshInfo i = mss::analyzeMesh(mesh(vertices, triangles));
    py::dict d;
    d["vertices"] = i.vertices;
    d["triangles"] = i.triangles;
    d["closed"] = i.closed;
    d["boundaryEdges"] = i.boundaryEdges;
    d["nonManifoldEdges"] = i.nonManifoldEdges;
    d["consistentlyOriented"] = i.consistentlyOriented;
    d["volume"] = std::abs(i.signedVolume);
    d["insideOut"] = i.signedVolume < 0;
    d["lower"] = list(i.lower);
    d["upper"] = list(i.upper);
    return d;
}

/// Other Python threads run while the core works on values already converted (it touches no Python object):
/// the pieces of a split are generated side by side. An exception leaves the scope with the lock taken again.
class WithoutGil {
public:
    WithoutGil() : state_(PyEval_SaveThread()) {}
    ~WithoutGil() { PyEval_RestoreThread(state_); }
    WithoutGil(const WithoutGil&) = delete;
    WithoutGil& operator=(const WithoutGil&) = delete;

private:
    PyThreadState* state_;
};

/// @p contacts: points of the surface to reach, each 6 numbers (point, normal into the grain).
py::dict generateMesh(const py::object& vertices, const py::object& triangles, const py::dict& opts,
                      const py::object& contacts) {
    mss::Settings st = settings(opts, mss::command::Generate);
    for (const mss::Plane& p : planes(contacts)) st.generate.contacts.push_back({p.point, p.normal});
    const mss::TriangleMesh m = mesh(vertices, triangles);
    mss::Result r;
    {
        WithoutGil unlocked;
        r = mss::generate(m, st.resolution, st.generate, st.supersample);
    }
    return result(r);
}

/// @p contacts: the points to reach, each 6 numbers (point, normal into the grain), as findContacts gives;
/// @p neighbours: None, or bytes on the same grid, non-zero where another grain is.
py::dict generateVoxels(const py::object& data, const py::object& shape, double voxelSize,
                        const py::object& origin, const py::dict& opts, const py::object& contacts,
                        const py::object& neighbours) {
    mss::GenerateOptions g = settings(opts, mss::command::Generate).generate;
    for (const mss::Plane& p : planes(contacts)) g.contacts.push_back({p.point, p.normal});
    if (!neighbours.is_none()) g.neighbours = voxels(neighbours, shape, voxelSize, origin);
    const mss::VoxelGrid v = voxels(data, shape, voxelSize, origin);
    mss::Result r;
    {
        WithoutGil unlocked;
        r = mss::generate(v, g);
    }
    return result(r);
}

/// The bytes of a vector of numbers, for numpy.frombuffer.
template <class T> py::object bytesOf(const std::vector<T>& v) {
    return py::object(py::handle<>(PyBytes_FromStringAndSize(reinterpret_cast<const char*>(v.data()),
                                                             Py_ssize_t(v.size() * sizeof(T)))));
}

/// Every contact of a labelled volume of @p shape within @p gap voxels (0: shared faces), read in slabs of
/// @p layers along x (and the finder's margin on each side): @p read(x0, x1) gives the int64 labels of layers
/// x0 .. x1 - 1, x fastest (Fortran order). As columns, each the bytes of an array of the contacts: a, b,
/// faces (int64), gap (double), point and normal (from a into b; 3 doubles a contact): a dict a contact cost
/// a batch of 10^5 grains half a GB. Two passes over the slabs: the peak is one slab, not the volume.
py::dict findContacts(const py::object& read, const py::object& shape, double voxelSize,
                      const py::object& origin, int layers, double gap) {
    if (layers < 1) throw std::invalid_argument("findContacts: layers must be >= 1");
    if (py::len(shape) != 3) throw std::invalid_argument("findContacts: the array must be 3-D");
    mss::GridSpec whole;
    whole.h = voxelSize;
    whole.origin = vec3(origin, "findContacts: origin");
    std::array<long long, 3> dims{};
    for (int a = 0; a < 3; ++a) dims[std::size_t(a)] = py::extract<long long>(shape[a]);
    mss::checkGridSize("findContacts", dims, 1, std::size_t(1) << 40);
    for (int a = 0; a < 3; ++a) whole.dims[std::size_t(a)] = int(dims[std::size_t(a)]);
    if (!(voxelSize > 0.0) || !std::isfinite(voxelSize) || !whole.origin.allFinite())
        throw std::invalid_argument("findContacts: voxel size must be > 0 and the origin finite");
    mss::ContactFinder finder(whole, gap);
    const int margin = finder.margin();
    for (int pass = 0; pass < 2; ++pass)
        for (int x0 = 0; x0 < whole.dims[0]; x0 += layers) {
            const int own = std::min(layers, whole.dims[0] - x0);
            const int lo = std::max(0, x0 - margin), hi = std::min(whole.dims[0], x0 + own + margin);
            mss::LabelGrid slab;
            slab.spec = whole;
            slab.spec.dims[0] = hi - lo;
            const py::object data = read(lo, hi);
            char* buf = nullptr;
            Py_ssize_t len = 0;
            if (!PyBytes_Check(data.ptr()) || PyBytes_AsStringAndSize(data.ptr(), &buf, &len) != 0 ||
                std::size_t(len) != slab.spec.size() * 8)
                throw std::invalid_argument("findContacts: a slab must be the bytes of its int64 labels");
            slab.labels.resize(slab.spec.size());
            std::memcpy(slab.labels.data(), buf, std::size_t(len));
            if (pass == 0)
                finder.count(slab, lo, x0 - lo, own);
            else
                finder.locate(slab, lo, x0 - lo, own);
        }
    const std::vector<mss::LabelContact>& found = finder.contacts();
    std::vector<std::int64_t> a, b, faces;
    std::vector<double> gaps, points, normals;
    for (const mss::LabelContact& c : found) {
        a.push_back(c.a);
        b.push_back(c.b);
        faces.push_back(c.faces);
        gaps.push_back(c.gap);
        points.insert(points.end(), {c.point.x(), c.point.y(), c.point.z()});
        normals.insert(normals.end(), {c.normal.x(), c.normal.y(), c.normal.z()});
    }
    py::dict out;
    out["a"] = bytesOf(a);
    out["b"] = bytesOf(b);
    out["faces"] = bytesOf(faces);
    out["gap"] = bytesOf(gaps);
    out["point"] = bytesOf(points);
    out["normal"] = bytesOf(normals);
    return out;
}

/// The numbers in the bytes @p data (numpy's tobytes()), as a vector of T; @p where and @p what name them in
/// the error.
template <class T> std::vector<T> numbersOf(const py::object& data, const char* where, const char* what) {
    char* buf = nullptr;
    Py_ssize_t len = 0;
    if (!PyBytes_Check(data.ptr()) || PyBytes_AsStringAndSize(data.ptr(), &buf, &len) != 0 ||
        std::size_t(len) % sizeof(T) != 0)
        throw std::invalid_argument(std::string(where) + ": " + what + " must be the bytes of an array of " +
                                    std::to_string(sizeof(T)) + "-byte numbers");
    std::vector<T> v(std::size_t(len) / sizeof(T));
    if (!v.empty()) std::memcpy(v.data(), buf, std::size_t(len));
    return v;
}

/// mss::clumpGaps of packed clumps: @p spheres an (n, 4) C-contiguous float64 array (x y z r a row), read
/// where it is (its buffer: copied three times, a 10^5-grain batch's peak rose by 110 MB), @p offsets the
/// bytes of int64 (clumps + 1), @p i and @p j of int64; the gaps as the bytes of doubles.
py::object clumpGaps(const py::object& spheres, const py::object& offsets, const py::object& i,
                     const py::object& j) {
    Py_buffer b;
    if (PyObject_GetBuffer(spheres.ptr(), &b, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) != 0) {
        PyErr_Clear();
        throw std::invalid_argument("clumpGaps: the spheres must be a C-contiguous array of float64");
    }
    struct Release {
        Py_buffer* b;
        ~Release() { PyBuffer_Release(b); }
    } release{&b};
    const std::string f = b.format ? b.format : "B";
    if ((f != "d" && f != "<d" && f != "=d") || b.itemsize != 8 || b.len % 32 != 0)
        throw std::invalid_argument("clumpGaps: the spheres must be rows x y z r of float64");
    const std::vector<std::int64_t> o = numbersOf<std::int64_t>(offsets, "clumpGaps", "the offsets");
    const std::vector<std::int64_t> a = numbersOf<std::int64_t>(i, "clumpGaps", "i");
    const std::vector<std::int64_t> c = numbersOf<std::int64_t>(j, "clumpGaps", "j");
    std::vector<double> out;
    {
        WithoutGil unlocked;
        out = mss::clumpGaps(static_cast<const double*>(b.buf), std::size_t(b.len / 32), o, a, c);
    }
    return bytesOf(out);
}

/// The bytes of a text (a sphere file, a batch's table).
py::object textBytes(const std::string& text) {
    return py::object(py::handle<>(PyBytes_FromStringAndSize(text.data(), Py_ssize_t(text.size()))));
}

/// mss::formatRows of @p ints (the bytes of int64, @p intCols a row) and @p values (of float64, @p cols a
/// row), as the bytes of the text; @p style "shortest" (Python's repr) or "g17" (printf's %.17g).
py::object formatRows(const py::object& ints, int intCols, const py::object& values, int cols,
                      const std::string& style, const std::string& sep, const std::string& end) {
    if (intCols < 0 || cols < 0 || intCols + cols == 0)
        throw std::invalid_argument("formatRows: give at least one column, got " + std::to_string(intCols) +
                                    " integer and " + std::to_string(cols) + " number columns");
    if (style != "shortest" && style != "g17")
        throw std::invalid_argument("formatRows: style must be 'shortest' or 'g17', got '" + style + "'");
    if (sep.size() != 1) throw std::invalid_argument("formatRows: the separator must be one character");
    const std::vector<std::int64_t> i = numbersOf<std::int64_t>(ints, "formatRows", "the integers");
    const std::vector<double> v = numbersOf<double>(values, "formatRows", "the numbers");
    const std::size_t rows = intCols > 0 ? i.size() / std::size_t(intCols) : v.size() / std::size_t(cols);
    if (i.size() != rows * std::size_t(intCols) || v.size() != rows * std::size_t(cols))
        throw std::invalid_argument("formatRows: " + std::to_string(i.size()) + " integers and " +
                                    std::to_string(v.size()) + " numbers are not rows of " +
                                    std::to_string(intCols) + " and " + std::to_string(cols));
    std::string text;
    {
        WithoutGil unlocked;
        text = mss::formatRows(i.data(), std::size_t(intCols), v.data(), std::size_t(cols), rows,
                               style == "g17" ? mss::NumberText::Precision17 : mss::NumberText::Shortest,
                               sep[0], end);
    }
    return textBytes(text);
}

/// mss::formatClumpAssembly of packed clumps: @p spheres the bytes of float64 rows x y z r, @p offsets of
/// int64 (clumps + 1), @p ids of int64 (clumps), @p heads of float64 (10 a clump).
py::object formatClumpAssembly(const py::object& spheres, const py::object& offsets, const py::object& ids,
                               const py::object& heads) {
    const std::vector<double> s = numbersOf<double>(spheres, "formatClumpAssembly", "the spheres");
    const std::vector<std::int64_t> o =
        numbersOf<std::int64_t>(offsets, "formatClumpAssembly", "the offsets");
    const std::vector<std::int64_t> d = numbersOf<std::int64_t>(ids, "formatClumpAssembly", "the ids");
    const std::vector<double> h = numbersOf<double>(heads, "formatClumpAssembly", "the mass rows");
    if (s.size() % 4 != 0 || o.size() != d.size() + 1 || h.size() != 10 * d.size())
        throw std::invalid_argument(
            "formatClumpAssembly: " + std::to_string(d.size()) + " clumps need " +
            std::to_string(d.size() + 1) + " offsets and " + std::to_string(10 * d.size()) +
            " mass numbers, and the spheres rows of 4; got " + std::to_string(o.size()) + ", " +
            std::to_string(h.size()) + " and " + std::to_string(s.size()));
    std::string text;
    {
        WithoutGil unlocked;
        text = mss::formatClumpAssembly(s.data(), s.size() / 4, o.data(), d.data(), h.data(), d.size());
    }
    return textBytes(text);
}

// with planes: the part of the solid on their allowed side (a fragment)
const char* const kNothingLeft =
    "massProperties: no part of the solid lies on the allowed side of the planes";
py::dict massMesh(const py::object& vertices, const py::object& triangles, const py::object& cuts) {
    const std::vector<mss::Plane> p = planes(cuts);
    const mss::TriangleMesh m = mesh(vertices, triangles);
    if (p.empty()) return mass(mss::meshMassProperties(m));
    const mss::TriangleMesh part = mss::clipMeshByPlanes(m, p);
    if (part.triangles.empty()) throw std::invalid_argument(kNothingLeft);
    return mass(mss::meshMassProperties(part));
}

py::dict massVoxels(const py::object& data, const py::object& shape, double voxelSize,
                    const py::object& origin, const py::object& cuts) {
    const std::vector<mss::Plane> p = planes(cuts);
    const mss::VoxelGrid v = voxels(data, shape, voxelSize, origin);
    if (p.empty()) return mass(mss::voxelMassProperties(v));
    const mss::VoxelGrid part = mss::cutVoxelsByPlanes(v, p);
    if (mss::countSolid(part) == 0) throw std::invalid_argument(kNothingLeft);
    return mass(mss::voxelMassProperties(part));
}

py::dict massSpheres(const py::object& centers, const py::object& radii, int resolution) {
    return mass(mss::sphereUnionMassProperties(spheres(centers, radii), resolution));
}

/// A mesh for Python: {vertices: bytes of (n, 3) doubles, triangles: bytes of (m, 3) int32}.
py::dict meshBytes(const mss::TriangleMesh& m) {
    std::vector<double> v;
    v.reserve(3 * m.vertices.size());
    for (const mss::Vec3& p : m.vertices) v.insert(v.end(), {p.x(), p.y(), p.z()});
    std::vector<std::int32_t> t;
    t.reserve(3 * m.triangles.size());
    for (const auto& tri : m.triangles) t.insert(t.end(), tri.begin(), tri.end());
    py::dict d;
    d["vertices"] = py::object(py::handle<>(
        PyBytes_FromStringAndSize(reinterpret_cast<const char*>(v.data()), Py_ssize_t(v.size() * 8))));
    d["triangles"] = py::object(py::handle<>(
        PyBytes_FromStringAndSize(reinterpret_cast<const char*>(t.data()), Py_ssize_t(t.size() * 4))));
    return d;
}

/// The union's boundary as a mesh (meshBytes) and the report's figures; @p options: mss surface's
/// (tolerance, maxEdge, maxTriangles).
py::dict unionSurface(const py::object& centers, const py::object& radii, const py::dict& options) {
    const mss::Settings st = settings(options, mss::command::Surface);
    const mss::SphereSet s = spheres(centers, radii);
    mss::SurfaceReport r;
    py::dict d = meshBytes(mss::unionSurface(s, st.surface, &r));
    d["subdivisions"] = r.subdivisions;
    d["volume"] = r.volume;
    d["unionVolume"] = r.unionVolume;
    d["longestEdge"] = r.longestEdge;
    d["smallestAngle"] = r.smallestAngle;
    return d;
}

/// The pieces of a mesh cut by a plane (6 numbers: point, normal): {above: [meshBytes], below: [...]}.
py::dict splitMesh(const py::object& vertices, const py::object& triangles, const py::object& plane) {
    const std::vector<mss::Plane> p = planes(py::list(py::make_tuple(plane)));
    const mss::MeshSplit split = mss::splitMeshByPlane(mesh(vertices, triangles), p[0]);
    py::dict d;
    for (const auto& [name, side] : {std::pair{"above", &split.above}, std::pair{"below", &split.below}}) {
        py::list l;
        for (const mss::TriangleMesh& m : *side) { // each piece with its mass properties (massMesh's)
            py::dict piece = meshBytes(m);
            piece["mass"] = mass(mss::meshMassProperties(m));
            l.append(piece);
        }
        d[name] = l;
    }
    return d;
}

double insideClearance(const py::object& vertices, const py::object& triangles, const py::object& point) {
    return mss::insideClearance(mesh(vertices, triangles), vec3(point, "insideClearance: point"));
}

void writeMesh(const py::object& vertices, const py::object& triangles, const std::string& path) {
    mss::writeMesh(mesh(vertices, triangles), path);
}

double sphereUnionVolume(const py::object& centers, const py::object& radii) {
    return mss::sphereUnionVolume(spheres(centers, radii));
}

py::dict scoreMesh(const py::object& vertices, const py::object& triangles, const py::object& centers,
                   const py::object& radii, int resolution, double offset, int supersample,
                   const py::object& cuts) {
    return score(mss::scoreSpheres(mesh(vertices, triangles), spheres(centers, radii), resolution, offset,
                                   supersample, planes(cuts)));
}

py::dict scoreVoxels(const py::object& data, const py::object& shape, double voxelSize,
                     const py::object& origin, const py::object& centers, const py::object& radii,
                     const py::object& cuts) {
    return score(
        mss::scoreSpheres(voxels(data, shape, voxelSize, origin), spheres(centers, radii), planes(cuts)));
}

mss::CompareOptions compareOptions(const py::dict& d) {
    return settings(d, mss::command::Compare).compare;
}

/// Monte Carlo scores: dice, diceError, eta, etaError, targetVolume(+Error), sphereVolume(+Error), samples,
/// seed.
py::dict exactScore(const mss::ExactScore& e) {
    py::dict d;
    d["dice"] = e.dice;
    d["diceError"] = e.diceError;
    d["eta"] = e.eta;
    d["etaError"] = e.etaError;
    d["targetVolume"] = e.targetVolume;
    d["targetVolumeError"] = e.targetVolumeError;
    d["sphereVolume"] = e.sphereVolume;
    d["sphereVolumeError"] = e.sphereVolumeError;
    d["samples"] = e.samples;
    d["seed"] = e.seed;
    return d;
}

py::dict comparison(const mss::Comparison& c) {
    py::dict d = score(c.score);
    d["spheres"] = c.spheres;
    d["protrusion"] = c.protrusion;
    py::list each;
    for (double v : c.sphereProtrusion) each.append(v);
    d["sphereProtrusion"] = each;
    d["smallestRadius"] = c.smallestRadius;
    d["massError"] = c.massError;
    d["centroidError"] = c.centroidError;
    d["inertiaError"] = c.inertiaError;
    d["insideBox"] = c.insideBox;
    py::list R;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) R.append(c.transform.rotation(i, j));
    d["rotation"] = R;
    d["translation"] = list(c.transform.translation);
    if (c.exact.samples > 0) d["exact"] = exactScore(c.exact);
    return d;
}

py::dict compareMesh(const py::object& vertices, const py::object& triangles, const py::object& centers,
                     const py::object& radii, const py::dict& opts) {
    return comparison(
        mss::compareSpheres(mesh(vertices, triangles), spheres(centers, radii), compareOptions(opts)));
}

py::dict compareVoxels(const py::object& data, const py::object& shape, double voxelSize,
                       const py::object& origin, const py::object& centers, const py::object& radii,
                       const py::dict& opts) {
    return comparison(mss::compareSpheres(voxels(data, shape, voxelSize, origin), spheres(centers, radii),
                                          compareOptions(opts)));
}

py::dict scoreExactMesh(const py::object& vertices, const py::object& triangles, const py::object& centers,
                        const py::object& radii, long long samples, long long seed, const py::object& cuts) {
    if (samples < 0 || seed < 0) throw std::invalid_argument("scoreExact: samples and seed must be >= 0");
    return exactScore(mss::scoreSpheresExact(mesh(vertices, triangles), spheres(centers, radii),
                                             std::size_t(samples), std::uint64_t(seed), planes(cuts)));
}

py::dict scoreExactVoxels(const py::object& data, const py::object& shape, double voxelSize,
                          const py::object& origin, const py::object& centers, const py::object& radii,
                          long long samples, long long seed, const py::object& cuts) {
    if (samples < 0 || seed < 0) throw std::invalid_argument("scoreExact: samples and seed must be >= 0");
    return exactScore(mss::scoreSpheresExact(voxels(data, shape, voxelSize, origin), spheres(centers, radii),
                                             std::size_t(samples), std::uint64_t(seed), planes(cuts)));
}

mss::Image2 image2(const py::object& data, int nx, int ny, double pixel, const py::object& origin) {
    if (nx < 1 || ny < 1) throw std::invalid_argument("spheropolygon: the image must be 2-D and not empty");
    const std::vector<double> o = doubles(origin, "spheropolygon: origin");
    if (o.size() != 2) throw std::invalid_argument("spheropolygon: origin must be (x, y)");
    mss::Image2 im(nx, ny, pixel, mss::Vec2(o[0], o[1]));
    char* buf = nullptr;
    Py_ssize_t len = 0;
    if (!PyBytes_Check(data.ptr()) || PyBytes_AsStringAndSize(data.ptr(), &buf, &len) != 0 ||
        std::size_t(len) != im.data.size())
        throw std::invalid_argument("spheropolygon: image data must be nx * ny bytes");
    for (std::size_t q = 0; q < im.data.size(); ++q) im.data[q] = buf[q] != 0;
    return im;
}

py::dict spheropolygonFit(const py::object& data, int nx, int ny, double pixel, const py::object& origin,
                          const py::dict& d) {
    mss::SpOptions o;
    if (d.has_key("vertices")) o.vertices = py::extract<int>(d["vertices"]);
    if (d.has_key("radius")) o.radius = py::extract<double>(d["radius"]);
    if (d.has_key("init")) o.init = mss::parseSpInit(py::extract<std::string>(d["init"]));
    if (d.has_key("inset")) o.inset = py::extract<bool>(d["inset"]);
    if (d.has_key("samplingRadius")) o.samplingRadius = py::extract<double>(d["samplingRadius"]);
    if (d.has_key("samples")) o.samples = py::extract<int>(d["samples"]);
    if (d.has_key("weight")) o.weight = py::extract<double>(d["weight"]);
    if (d.has_key("cutoff")) o.cutoff = py::extract<long long>(d["cutoff"]);
    if (d.has_key("tolerance")) o.tolerance = py::extract<double>(d["tolerance"]);
    if (d.has_key("maxIterations")) o.maxIterations = py::extract<int>(d["maxIterations"]);
    if (d.has_key("relocations")) o.relocations = py::extract<int>(d["relocations"]);
    if (d.has_key("regionVertices")) o.regionVertices = py::extract<bool>(d["regionVertices"]);
    if (d.has_key("regionTurning")) o.regionTurning = py::extract<double>(d["regionTurning"]);
    if (d.has_key("vertexRadii")) o.vertexRadii = py::extract<bool>(d["vertexRadii"]);
    if (d.has_key("minRadius") && !py::object(d["minRadius"]).is_none())
        o.minRadius = py::extract<double>(d["minRadius"]);
    const mss::SpResult r = mss::fitSpheropolygon(image2(data, nx, ny, pixel, origin), o);
    py::dict out;
    py::list v, h;
    for (const mss::Vec2& p : r.sp.vertices) v.append(py::make_tuple(p.x(), p.y()));
    for (long long e : r.history) h.append(e);
    out["vertices"] = v;
    out["spheroradius"] = r.sp.radius;
    if (!r.sp.radii.empty()) {
        py::list radii;
        for (double x : r.sp.radii) radii.append(x);
        out["radii"] = radii;
    }
    if (o.regionVertices) {
        out["regions"] = r.regions;
        out["regionsFilled"] = r.regionsFilled;
        out["regionsMissed"] = r.regionsMissed;
    }
    out["errorPixels"] = r.errorPixels;
    out["particlePixels"] = r.particlePixels;
    out["error"] = r.error;
    out["iterations"] = r.iterations;
    out["history"] = h;
    const mss::Roundness R = mss::roundness(r.sp);
    out["roundness"] = R.roundness;
    out["area"] = R.area;
    out["perimeter"] = R.perimeter;
    return out;
}

/// The convex and concave regions of a particle's boundary: ([(first, last, coreFirst, coreLast, centre,
/// turning), ...],
/// [(x, y), ...] of the smoothed boundary the indices refer to).
py::tuple spheropolygonRegions(const py::object& data, int nx, int ny, double pixel, const py::object& origin,
                               double minTurning) {
    std::vector<mss::Vec2> boundary;
    const std::vector<mss::SpRegion> regions =
        mss::boundaryRegions(image2(data, nx, ny, pixel, origin), minTurning, &boundary);
    py::list r, b;
    for (const mss::SpRegion& x : regions)
        r.append(py::make_tuple(x.first, x.last, x.coreFirst, x.coreLast, x.centre, x.turning));
    for (const mss::Vec2& p : boundary) b.append(py::make_tuple(p.x(), p.y()));
    return py::make_tuple(r, b);
}

py::tuple readSpheres(const std::string& path, long long clumpId) {
    const mss::SphereSet s = mss::readSpheres(path, clumpId);
    py::list c, r;
    for (std::size_t i = 0; i < s.size(); ++i) {
        for (int a = 0; a < 3; ++a) c.append(s.centers[i][a]);
        r.append(s.radii[i]);
    }
    return py::make_tuple(c, r);
}

void writeSpheres(const py::object& centers, const py::object& radii, const std::string& path) {
    mss::writeSpheres(spheres(centers, radii), path);
}

/// writeSpheres' text for @p path's extension, as bytes (written and digested by the caller).
py::object formatSpheres(const py::object& centers, const py::object& radii, const std::string& path) {
    return textBytes(mss::formatSpheres(spheres(centers, radii), path));
}

// A message may quote bytes of a file that are not UTF-8 (0xB5...): decode with backslash escapes, so that
// the Python exception always carries the message (PyErr_SetString would leave it empty).
void setError(PyObject* type, const char* what) {
    PyObject* msg = PyUnicode_DecodeUTF8(what, Py_ssize_t(std::strlen(what)), "backslashreplace");
    if (!msg) {
        PyErr_Clear();
        msg = PyUnicode_FromString("(message not decodable)");
    }
    PyErr_SetObject(type, msg);
    Py_XDECREF(msg);
}
void translateInvalid(const std::invalid_argument& e) {
    setError(PyExc_ValueError, e.what());
}
void translateRuntime(const std::runtime_error& e) {
    setError(PyExc_RuntimeError, e.what());
}
void translateInterrupted(const mss::Interrupted&) { // Ctrl-C inside the core: Python's own exception
    mss::clearStop();
    PyErr_SetNone(PyExc_KeyboardInterrupt);
}

/// Ctrl-C while the core works without the GIL: Python's handler only sets a flag, which the core's
/// checkpoints ask for here (the main thread runs the handler; it raises KeyboardInterrupt, kept as a stop).
bool pythonAsksToStop() {
    const PyGILState_STATE g = PyGILState_Ensure();
    const bool stop = PyErr_CheckSignals() != 0;
    if (stop) PyErr_Clear(); // raised again as KeyboardInterrupt by translateInterrupted
    PyGILState_Release(g);
    return stop;
}

void translateBadAlloc(const std::bad_alloc&) { // memoryLimit allows more than this machine could give
    setError(PyExc_RuntimeError,
             "out of memory: the machine could not give what this run needs; lower the "
             "resolution, or set memoryLimit to the memory the machine has (default 8 GiB) "
             "to be told before");
}

} // namespace

/// The OpenMP thread count of this process from now on (a forked batch worker: 1, see _batch.py).
void setOmpThreads(int n) {
    if (n < 1) throw std::invalid_argument("setOmpThreads: n must be >= 1, got " + std::to_string(n));
#ifdef _OPENMP
    omp_set_num_threads(n);
#endif
}

/// The core's work limit for the Python front ends' own heavy steps (sweeps), with its message.
void checkWork(const std::string& where, const std::string& what, double seconds, double maxWork,
               const std::string& lighter) {
    mss::checkWork(where, {what, seconds}, maxWork, lighter);
}

BOOST_PYTHON_MODULE(_mss) {
    py::register_exception_translator<std::invalid_argument>(&translateInvalid);
    py::register_exception_translator<std::runtime_error>(&translateRuntime);
    py::register_exception_translator<std::bad_alloc>(&translateBadAlloc);
    py::register_exception_translator<mss::Interrupted>(&translateInterrupted); // after runtime_error: first
    mss::setStopPoll(pythonAsksToStop);
    mss::showProgressOnStandardError(); // as the command line shows it
    py::scope().attr("__doc__") = "yade-mss core (C++). Use the yade_mss package, which wraps this module.";
    py::def("checkWork", checkWork,
            (py::arg("where"), py::arg("what"), py::arg("seconds"), py::arg("maxWork"), py::arg("lighter")),
            "Refuses (ValueError) an estimate over maxWork seconds.");
    py::def(
        "version", +[]() { return std::string(mss::version()); },
        "This library's version (the CMake project's).");
    py::def("setOmpThreads", setOmpThreads, (py::arg("n")), "OpenMP threads of this process from now on.");
    py::def("readMesh", readMesh, (py::arg("path")), "Mesh file -> (flat vertices, flat triangles).");
    py::def("readNpy", readNpy, (py::arg("path"), py::arg("label") = -1));
    py::def("voxelizeMesh", voxelizeMesh, (py::arg("vertices"), py::arg("triangles"), py::arg("resolution")));
    py::def("meshInfo", meshInfo, (py::arg("vertices"), py::arg("triangles")));
    py::def("optionTable", optionTable, "The option table: a dict per row.");
    py::def("fileFormats", fileFormats, "The format table: a dict per row.");
    py::def("parseOption", parseOption, (py::arg("name"), py::arg("command"), py::arg("text")),
            "An option's value from its text, as the command line parses it.");
    py::def(
        "generateMesh", generateMesh,
        (py::arg("vertices"), py::arg("triangles"), py::arg("options"), py::arg("contacts") = py::list()));
    py::def("generateVoxels", generateVoxels,
            (py::arg("data"), py::arg("shape"), py::arg("voxelSize"), py::arg("origin"), py::arg("options"),
             py::arg("contacts") = py::list(), py::arg("neighbours") = py::object()));
    py::def("findContacts", findContacts,
            (py::arg("read"), py::arg("shape"), py::arg("voxelSize"), py::arg("origin"), py::arg("layers"),
             py::arg("gap") = 1.0));
    py::def("massMesh", massMesh,
            (py::arg("vertices"), py::arg("triangles"), py::arg("planes") = py::list()));
    py::def("massVoxels", massVoxels,
            (py::arg("data"), py::arg("shape"), py::arg("voxelSize"), py::arg("origin"),
             py::arg("planes") = py::list()));
    py::def("massSpheres", massSpheres, (py::arg("centers"), py::arg("radii"), py::arg("resolution") = 200));
    py::def("unionSurface", unionSurface, (py::arg("centers"), py::arg("radii"), py::arg("options")),
            "The boundary of the spheres' union as a closed mesh (mss surface).");
    py::def("splitMesh", splitMesh, (py::arg("vertices"), py::arg("triangles"), py::arg("plane")),
            "The pieces of a closed mesh on either side of a plane, each closed: {above, below}, lists of "
            "{vertices, triangles, mass} (mass: as massMesh gives it).");
    py::def("insideClearance", insideClearance, (py::arg("vertices"), py::arg("triangles"), py::arg("point")),
            "Distance from a point inside a closed mesh to its surface; 0 outside.");
    py::def("writeMesh", writeMesh, (py::arg("vertices"), py::arg("triangles"), py::arg("path")),
            "Writes a mesh by extension (.stl, .obj, .ply), atomically.");
    py::def("sphereUnionVolume", sphereUnionVolume, (py::arg("centers"), py::arg("radii")),
            "The exact volume of the spheres' union.");
    py::def("scoreMesh", scoreMesh,
            (py::arg("vertices"), py::arg("triangles"), py::arg("centers"), py::arg("radii"),
             py::arg("resolution") = 100, py::arg("offset") = 0.37, py::arg("supersample") = 1,
             py::arg("planes") = py::list()));
    py::def("scoreVoxels", scoreVoxels,
            (py::arg("data"), py::arg("shape"), py::arg("voxelSize"), py::arg("origin"), py::arg("centers"),
             py::arg("radii"), py::arg("planes") = py::list()));
    py::def("scoreExactMesh", scoreExactMesh,
            (py::arg("vertices"), py::arg("triangles"), py::arg("centers"), py::arg("radii"),
             py::arg("samples"), py::arg("seed"), py::arg("planes") = py::list()));
    py::def("scoreExactVoxels", scoreExactVoxels,
            (py::arg("data"), py::arg("shape"), py::arg("voxelSize"), py::arg("origin"), py::arg("centers"),
             py::arg("radii"), py::arg("samples"), py::arg("seed"), py::arg("planes") = py::list()));
    py::def("compareMesh", compareMesh,
            (py::arg("vertices"), py::arg("triangles"), py::arg("centers"), py::arg("radii"),
             py::arg("options")));
    py::def("compareVoxels", compareVoxels,
            (py::arg("data"), py::arg("shape"), py::arg("voxelSize"), py::arg("origin"), py::arg("centers"),
             py::arg("radii"), py::arg("options")));
    py::def("spheropolygon", spheropolygonFit,
            (py::arg("data"), py::arg("nx"), py::arg("ny"), py::arg("pixel"), py::arg("origin"),
             py::arg("options")));
    py::def("spheropolygonRegions", spheropolygonRegions,
            (py::arg("data"), py::arg("nx"), py::arg("ny"), py::arg("pixel"), py::arg("origin"),
             py::arg("minTurning")));
    py::def("readSpheres", readSpheres, (py::arg("path"), py::arg("clumpId") = -1));
    py::def("writeSpheres", writeSpheres, (py::arg("centers"), py::arg("radii"), py::arg("path")));
    py::def("clumpGaps", clumpGaps, (py::arg("spheres"), py::arg("offsets"), py::arg("i"), py::arg("j")),
            "The least gap between packed clumps i[n] and j[n] (bytes in and out).");
    py::def("formatSpheres", formatSpheres, (py::arg("centers"), py::arg("radii"), py::arg("path")));
    py::def(
        "formatRows", formatRows,
        (py::arg("ints"), py::arg("intCols"), py::arg("values"), py::arg("cols"), py::arg("style"),
         py::arg("sep"), py::arg("end")),
        "Rows of numbers as text (bytes in and out): integers, then numbers, as repr or %.17g writes them.");
    py::def("formatClumpAssembly", formatClumpAssembly,
            (py::arg("spheres"), py::arg("offsets"), py::arg("ids"), py::arg("heads")),
            "A batch's assembly.txt body of packed clumps (bytes in and out).");
}
