// The option table (mss/options.hpp): its defaults are the core's, its checks name the option.
#include "mss/options.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>

using namespace mss;

TEST(Options, TableDefaultsAreTheStructDefaults) {
    const GenerateOptions plain;
    const GenerateOptions table = settingsFrom({}, command::Generate).generate;
    EXPECT_EQ(table.nSpheres, plain.nSpheres);
    EXPECT_EQ(table.maxIterations, plain.maxIterations);
    EXPECT_EQ(table.deltaMin, plain.deltaMin);
    EXPECT_EQ(table.keepSymmetry, plain.keepSymmetry);
    EXPECT_EQ(table.threads, plain.threads);
    EXPECT_EQ(table.clip, plain.clip);
    EXPECT_EQ(table.refill, plain.refill);
    EXPECT_EQ(table.method, plain.method);
    EXPECT_FALSE(table.maxProtrusion.has_value());
    const Settings st = settingsFrom({}, command::Generate);
    EXPECT_EQ(st.resolution.resolution, 100);
    EXPECT_EQ(st.resolution.memoryLimit, kDefaultMemoryLimit);
    const CompareOptions plainC, tableC = settingsFrom({}, command::Compare).compare;
    EXPECT_EQ(tableC.resolution, plainC.resolution);
    EXPECT_EQ(tableC.offset, plainC.offset);
    EXPECT_EQ(tableC.supersample, plainC.supersample);
    EXPECT_EQ(tableC.checkFrame, plainC.checkFrame);
}

TEST(Options, EveryDefaultParsesAndEveryNameHasOneFlag) {
    std::map<std::string, std::string> flags;
    for (const OptionSpec& s : optionTable()) {
        if (*s.fallback) EXPECT_NO_THROW(parseOption(s, s.fallback)) << s.name;
        auto [it, fresh] = flags.emplace(s.name, s.flag);
        EXPECT_EQ(it->second, s.flag) << s.name;
    }
}

TEST(Options, ValuesAreCheckedAndNamed) {
    try {
        settingsFrom({{"eta", 1.5}}, command::Generate);
        FAIL() << "eta 1.5 taken";
    } catch (const OptionError& e) {
        EXPECT_EQ(e.option(), "eta");
        EXPECT_EQ(std::string(e.what()), "generate: eta must be in [0, 1), got 1.5");
        EXPECT_EQ(e.detail(), " must be in [0, 1), got 1.5");
    }
    EXPECT_THROW(settingsFrom({{"nSpheres", 2.5}}, command::Generate), OptionError); // a number, not a count
    EXPECT_THROW(settingsFrom({{"offset", 0.1}}, command::Generate),
                 OptionError); // compare's, not generate's
    try {
        settingsFrom({{"nSphere", 3LL}}, command::Generate);
        FAIL();
    } catch (const OptionError& e) {
        EXPECT_NE(std::string(e.what()).find("did you mean 'nSpheres'"), std::string::npos) << e.what();
    }
    EXPECT_THROW(settingsFrom({{"voxelSize", 0.1}, {"resolution", 30LL}}, command::Generate), OptionError);
}

TEST(Options, TextIsParsedAsTheCommandLineGivesIt) {
    const Settings st = settingsFrom({{"nSpheres", parseOption(*findOption("nSpheres"), "7")},
                                      {"origin", parseOption(*findOption("origin"), "1,2,3")},
                                      {"method", parseOption(*findOption("method"), "paper")},
                                      {"voxelSize", parseOption(*findOption("voxelSize"), "0.5")}},
                                     command::Generate);
    EXPECT_EQ(st.generate.nSpheres, 7);
    EXPECT_EQ(st.origin, Vec3(1, 2, 3));
    EXPECT_EQ(st.generate.method, Method::Paper);
    EXPECT_EQ(st.resolution.voxelSize, 0.5);
    EXPECT_EQ(st.resolution.resolution, 0);
    EXPECT_THROW(parseOption(*findOption("nSpheres"), "7.5"), OptionError);
    EXPECT_THROW(parseOption(*findOption("origin"), "1,2"), OptionError);
    EXPECT_THROW(parseOption(*findOption("method"), "fast"), OptionError);
    EXPECT_THROW(parseOption(*findOption("planes"), "0,0,0,0,0,0"), OptionError); // a zero normal
}

TEST(Options, ValidateOptionsUsesTheTableRanges) {
    GenerateOptions o;
    o.nSpheres = 3;
    o.threads = 2000;
    try {
        validateOptions(o);
        FAIL();
    } catch (const OptionError& e) {
        EXPECT_EQ(std::string(e.what()), "generate: threads must be in [0, 1024], got 2000");
    }
}
