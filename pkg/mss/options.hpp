// The option table: every option of every command, once (name, command-line flag, Python keyword, type,
// default, range, unit, help, the commands that take it). The command line, the Python binding, the Python
// signatures' docstrings and the core's checks are made from it; tests/python/test_options.py fails when a
// front end drifts from it.
#pragma once

#include "mss/compare.hpp"
#include "mss/generate.hpp"
#include "mss/planes.hpp"
#include "mss/surface.hpp"
#include "mss/voxelize.hpp"

#include <map>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

namespace mss {

/// What kind of value an option holds.
enum class OptionType {
    Integer, ///< a whole number within [low, high]
    Number,  ///< a real number within the range (non-finite only where the range allows)
    Flag,    ///< on or off; the flag switches the default (a default of on has a "--no-..." flag)
    Choice,  ///< one of the words in choices ("optimized|paper")
    Text,    ///< a word or a path
    Point,   ///< X,Y,Z (world units)
    Point2,  ///< X,Y (world units; held as X,Y,0)
    Planes,  ///< PX,PY,PZ,NX,NY,NZ, repeatable: a point and a normal each
    Files,   ///< several paths
};

/// The commands an option belongs to (bits of OptionSpec::commands). The command line's `mss COMMAND` and
/// the Python function of the same name (compare: compareMany) take the same options.
namespace command {
constexpr unsigned Generate = 1, Compare = 2, Info = 4, Batch = 8, Preview = 16, Curve = 32,
                   Spheropolygon = 64, Ochart = 128, Export = 256, Surface = 512, Triaxial = 1024;
}

/// One row of the table.
struct OptionSpec {
    const char* name; ///< the option's name in the core and its messages; the Python keyword
    const char* flag; ///< the command line's spelling ("" where only Python takes it)
    bool python;      ///< whether the Python function takes it as a keyword
    OptionType type;
    const char* fallback;   ///< the default as text ("" = none: unset, or as help says)
    double low, high;       ///< the range (Integer, Number)
    bool lowOpen, highOpen; ///< whether the range excludes its end
    const char* choices;    ///< Choice: the words, '|'-separated
    const char* unit;       ///< "world units", "voxels", "GiB", or ""
    const char* metavar;    ///< the value's placeholder in --help
    const char* help;
    unsigned commands; ///< command:: bits
};

/// The whole table, in the order --help shows it.
const std::vector<OptionSpec>& optionTable();

/// The row of @p name for @p cmd (a command:: bit; 0: any command); null when there is none.
const OptionSpec* findOption(const std::string& name, unsigned cmd = 0);

/// A bad option value or an unknown option: what() is "WHERE: NAME DETAIL" ("generate: eta must be in [0, 1),
/// got 1.5"); a front end that spells the option otherwise (the command line's flag) puts its spelling in
/// front of detail().
class OptionError : public std::invalid_argument {
public:
    OptionError(const std::string& where, const std::string& option, const std::string& detail)
        : std::invalid_argument(where + ": " + option + detail), option_(option), detail_(detail) {}
    const std::string& option() const { return option_; }
    const std::string& detail() const { return detail_; }

private:
    std::string option_, detail_;
};

/// An option's value, as its type holds it.
using OptionValue =
    std::variant<bool, long long, double, std::string, Vec3, std::vector<Plane>, std::vector<std::string>>;
/// Values by option name: what a front end was given.
using OptionValues = std::map<std::string, OptionValue>;

/// The value of @p text as @p spec's type ("3", "0.5", "1,2,3", "optimized"). @throws OptionError
OptionValue parseOption(const OptionSpec& spec, const std::string& text);

/// @throws OptionError when @p value is not of @p spec's type or outside its range or choices.
void checkOption(const OptionSpec& spec, const OptionValue& value);

/// Levenshtein distance of two names, for "did you mean" on an unknown option (every front end's).
std::size_t editDistance(const std::string& a, const std::string& b);

/// The range of an Integer or Number row as text: ">= 1", "in [0, 1)".
std::string optionRange(const OptionSpec& spec);

/// What a generation, a comparison or a reading of voxels was asked for, with the defaults of the table.
struct Settings {
    GenerateOptions generate;
    Resolution resolution; ///< a mesh's generation grid: voxelSize if given, else resolution (default 100)
    int supersample = 1;
    CompareOptions compare;
    double voxelSize = 0.0; ///< given voxel edge (world units), 0 = not given
    Vec3 origin = Vec3::Zero();
    bool originGiven = false;
    long long label = -1;     ///< -1 = not given
    long long clumpId = -1;   ///< -1 = not given
    bool keepContacts = true; ///< a labelled volume's grain: reach its neighbours (GenerateOptions::contacts)
    double contactGap = 1.0;  ///< voxels: grains within it are in contact (findContacts' gap)
    SurfaceOptions surface;   ///< mss surface: the mesh of the spheres' union
    /// A factor on the grain's coordinates as read (a mesh's vertices; a voxel volume's voxel size and
    /// origin): 1e-3 makes a mesh in millimetres one in metres. Applied by the front ends as they read.
    double scale = 1.0;
};

/// Settings from the values of command @p cmd (a command:: bit): each value checked against its row (type,
/// range); a name the command does not take is an error that suggests the nearest it takes.
/// @throws OptionError
Settings settingsFrom(const OptionValues& values, unsigned cmd);

} // namespace mss
