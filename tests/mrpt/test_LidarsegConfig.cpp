#include <fstream>
#include <stdexcept>
#include <string>

#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "TempFiles.h"
#include "lidarseg/mrpt/LidarsegConfig.h"
#include "lidarseg/mrpt/OdometryConfig.h"
#include "lidarseg/mrpt/SegmentationConfig.h"
#include "lidarseg/mrpt/SimulationConfig.h"

namespace lidarseg::mrpt_adapter {
namespace {

using lidarseg::testing::writeTemp;

std::string errorOf(const std::string& path) {
  try {
    LidarsegConfig::loadFile(path);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(LidarsegConfig, TheShippedDefaultFileLoadsWithEveryStampKey) {
  const std::string path = std::string(LIDARSEG_CONFIG_DIR) + "/default.ini";
  const LidarsegConfig c = LidarsegConfig::loadFile(path);
  EXPECT_EQ(c.icp.maxIterations, 60u);  // [icp] is read
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  for (const auto& k : stampKeys()) EXPECT_NE(text.find("\n" + k + " "), std::string::npos) << k;
}

// Decision 110: the ICP baseline without a config file (or without [icp] keys) is the one
// config/default.ini configures for accuracy, not MRPT's faster defaults; a key given
// replaces its value alone.
TEST(LidarsegConfig, TheIcpBaselineWithoutAConfigIsTheShippedOne) {
  const LidarsegConfig none;
  const LidarsegConfig shipped = LidarsegConfig::loadFile(std::string(LIDARSEG_CONFIG_DIR) + "/default.ini");
  EXPECT_EQ(none.icp.corresponding_points_decimation, 1u);
  EXPECT_DOUBLE_EQ(none.icp.thresholdDist, 0.5);
  EXPECT_EQ(none.icp.maxIterations, 60u);
  EXPECT_EQ(none.icp.corresponding_points_decimation, shipped.icp.corresponding_points_decimation);
  EXPECT_DOUBLE_EQ(none.icp.thresholdDist, shipped.icp.thresholdDist);
  EXPECT_EQ(none.icp.maxIterations, shipped.icp.maxIterations);
  EXPECT_DOUBLE_EQ(none.icp.thresholdAng, shipped.icp.thresholdAng);
  const LidarsegConfig no_icp = LidarsegConfig::loadFile(writeTemp("no-icp.ini", "[matcher]\niterations = 2\n"));
  EXPECT_EQ(no_icp.icp.corresponding_points_decimation, 1u);
  EXPECT_EQ(no_icp.icp.maxIterations, 60u);
  const LidarsegConfig one_key = LidarsegConfig::loadFile(writeTemp("one-icp-key.ini", "[icp]\nmaxIterations = 17\n"));
  EXPECT_EQ(one_key.icp.maxIterations, 17u);
  EXPECT_EQ(one_key.icp.corresponding_points_decimation, 1u);
  EXPECT_DOUBLE_EQ(one_key.icp.thresholdDist, 0.5);
}

TEST(LidarsegConfig, AMisspeltSectionIsAnErrorNamingFileAndLine) {
  const std::string path = writeTemp("misspelt.ini", "[matcher]\niterations = 4\n\n[matchr]\niterations = 5\n");
  const std::string e = errorOf(path);
  EXPECT_NE(e.find(path + ":4"), std::string::npos) << e;
  EXPECT_NE(e.find("[matchr]"), std::string::npos) << e;
}

TEST(LidarsegConfig, IcpAndStampsAreReadFromYamlAsFromIni) {
  const std::string yaml =
      writeTemp("run.yaml", "icp:\n  maxIterations: 17\nstamps:\n  max_time_gap_s: 2.5\nodometry:\n  keyframe_distance_m: 0.2\n");
  const LidarsegConfig c = LidarsegConfig::loadFile(yaml);
  EXPECT_EQ(c.icp.maxIterations, 17u);
  EXPECT_DOUBLE_EQ(c.stamps.max_time_gap_s, 2.5);
  EXPECT_DOUBLE_EQ(c.odometry.keyframe_distance_m, 0.2);
}

TEST(LidarsegConfig, ABadStampValueNamesItsKeyAndLine) {
  const std::string path = writeTemp("stamps.ini", "[stamps]\nmax_speed_mps = -3\n");
  const std::string e = errorOf(path);
  EXPECT_NE(e.find("max_speed_mps"), std::string::npos) << e;
  EXPECT_NE(e.find(":2"), std::string::npos) << e;
}

TEST(LidarsegConfig, SizesAreCappedBeforeAnyParserRuns) {
  EXPECT_NE(errorOf("/dev/zero").find("larger than"), std::string::npos) << errorOf("/dev/zero");
  EXPECT_NE(errorOf(LIDARSEG_TEST_TMP_DIR).find("is a directory"), std::string::npos);
  const std::string deep = writeTemp("deep.yaml", "odometry:\n  level: " + std::string(20000, '[') + "\n");
  const std::string e = errorOf(deep);
  EXPECT_NE(e.find(deep + ":2: YAML nested deeper than"), std::string::npos) << e;
  std::string indented = "odometry:\n";
  for (int k = 1; k < 200; ++k) indented += std::string(2 * static_cast<std::size_t>(k), ' ') + "k" + std::to_string(k) + ":\n";
  EXPECT_NE(errorOf(writeTemp("indented.yaml", indented)).find("nested deeper"), std::string::npos);
}

// Issue 16, [icp]: MRPT's own reader took `thresholdDist = nan` (every ICP pose then 0, 0),
// ignored unknown keys and typos, read "1e3" as 1 and "-5" as 4294967291.
TEST(LidarsegConfig, TheIcpSectionIsStrictLikeTheOthers) {
  const std::string nan = writeTemp("icp-nan.ini", "[icp]\nmaxIterations = 20\nthresholdDist = nan\n");
  EXPECT_EQ(errorOf(nan).rfind(nan + ":3 [icp] thresholdDist: 'nan' is out of range: thresholdDist must be finite", 0),
            0u)
      << errorOf(nan);
  const std::string unknown = writeTemp("icp-foo.ini", "[icp]\nmaxIterations = 20\n\nfoo = 1\n");
  EXPECT_EQ(errorOf(unknown).rfind(unknown + ":4 [icp] foo: unknown key", 0), 0u) << errorOf(unknown);
  const std::string typo = writeTemp("icp-typo.yaml", "icp:\n  maxIteration: 1\n");
  EXPECT_EQ(errorOf(typo).rfind(typo + ":2 [icp] maxIteration: unknown key", 0), 0u) << errorOf(typo);
  const std::string radians = writeTemp("icp-rad.ini", "[icp]\nthresholdAng = 0.0262\n");
  EXPECT_NE(errorOf(radians).find(":2 [icp] thresholdAng: unknown key (MRPT reads this angle in degrees as "
                                  "thresholdAng_DEG)"),
            std::string::npos)
      << errorOf(radians);
  for (const char* bad : {"maxIterations = 1000000000", "maxIterations = -5", "maxIterations = 2.5",
                          "corresponding_points_decimation = 0", "ALFA = 0", "thresholdAng_DEG = inf",
                          "doRANSAC = 2", "ICP_algorithm = icpFast", "ransac_minSetSize = 30"}) {
    const std::string path = writeTemp("icp-bad.ini", std::string("[icp]\n") + bad + "\n");
    const std::string e = errorOf(path);
    const std::string key = std::string(bad).substr(0, std::string(bad).find(' '));
    EXPECT_EQ(e.rfind(path + ":2 [icp] " + key, 0), 0u)
        << bad << ": " << e;
  }
  const std::string good = writeTemp("icp-good.ini",
                                     "[icp]\nmaxIterations = 1e3\nthresholdAng_DEG = 1.5\nICP_algorithm = "
                                     "icpLevenbergMarquardt\ndoRANSAC = true\nthresholdDist = 0.4\n");
  const LidarsegConfig c = LidarsegConfig::loadFile(good);
  EXPECT_EQ(c.icp.maxIterations, 1000u);
  EXPECT_NEAR(c.icp.thresholdAng, 1.5 * M_PI / 180.0, 1e-12);
  EXPECT_EQ(c.icp.ICP_algorithm, mrpt::slam::icpLevenbergMarquardt);
  EXPECT_TRUE(c.icp.doRANSAC);
  EXPECT_DOUBLE_EQ(c.icp.thresholdDist, 0.4);
  // The shipped [icp] keeps what MRPT read from it: its default angular threshold.
  const LidarsegConfig shipped = LidarsegConfig::loadFile(std::string(LIDARSEG_CONFIG_DIR) + "/default.ini");
  EXPECT_DOUBLE_EQ(shipped.icp.thresholdAng, mrpt::slam::CICP::TConfigParams{}.thresholdAng);
  EXPECT_DOUBLE_EQ(shipped.icp.thresholdDist, 0.5);
  EXPECT_EQ(shipped.icp.corresponding_points_decimation, 1u);
}

// Issue 16, class "configuration files": what a parser would drop or ignore silently is an
// error naming the file, the line and the key or section.
TEST(LidarsegConfig, DuplicatesAndStrayKeysAreErrorsNamingFileLineAndKey) {
  const std::string twice = writeTemp("twice.yaml",
                                      "segmentation:\n  wd_threshold_m: 0.05\nmatcher:\n  iterations: 3\n"
                                      "segmentation:\n  wd_min_points: 4\n");
  EXPECT_EQ(errorOf(twice), twice + ":5: section 'segmentation' given twice (first at line 1); the parser would "
                                    "keep only the last");
  const std::string key_twice = writeTemp("keytwice.yaml", "matcher:\n  iterations: 3\n  # again\n  iterations: 4\n");
  EXPECT_EQ(errorOf(key_twice).rfind(key_twice + ":4 [matcher] iterations: given twice (first at line 2)", 0), 0u)
      << errorOf(key_twice);
  // The configuration store ignores case: `Iterations` is the same key (the last would win).
  const std::string case_twice = writeTemp("casetwice.yaml", "matcher:\n  iterations: 3\n  Iterations: 400\n");
  EXPECT_EQ(errorOf(case_twice).rfind(case_twice + ":3 [matcher] Iterations: given twice (first at line 2)", 0), 0u)
      << errorOf(case_twice);
  const std::string ini_twice = writeTemp("keytwice.ini", "[matcher]\niterations = 3\n[odometry]\n[Matcher]\niterations = 4\n");
  EXPECT_EQ(errorOf(ini_twice).rfind(ini_twice + ":5 [Matcher] iterations: given twice (first at line 2)", 0), 0u)
      << errorOf(ini_twice);
  const std::string stray = writeTemp("stray.ini", "; comment\niterations = 3\n[matcher]\nmax_segments = 64\n");
  EXPECT_EQ(errorOf(stray), stray + ":2: key 'iterations' before any [section] (every key belongs to a section)");
  // A nameless section's keys, a value without a key and text after a section's ']' were
  // dropped or read as another section without a word (issue 16).
  const std::string nameless = writeTemp("nameless.ini", "[]\niterations = 1000000000\n");
  EXPECT_EQ(errorOf(nameless), nameless + ":1: '[]' names no section (its keys would be dropped)");
  const std::string blank_name = writeTemp("blankname.ini", "[matcher]\niterations = 3\n[ ]\niterations = 4\n");
  EXPECT_EQ(errorOf(blank_name), blank_name + ":3: '[ ]' names no section (its keys would be dropped)");
  const std::string no_key = writeTemp("nokey.ini", "[matcher]\n= 1000000000\n");
  EXPECT_EQ(errorOf(no_key), no_key + ":2: '= 1000000000' gives a value to no key (the line would be dropped)");
  const std::string trailing = writeTemp("trailing.ini", "[matcher]x\niterations = 3\n");
  EXPECT_EQ(errorOf(trailing), trailing + ":1: '[matcher]x': text after the section's ']' (only a comment may follow)");
  const std::string commented = writeTemp("commented.ini", "[matcher] ; the matcher\niterations = 3\n");
  EXPECT_EQ(LidarsegConfig::loadFile(commented).odometry.matcher.iterations, 3u);
  // An editor's byte-order mark before the first section is no part of it.
  const std::string bom = writeTemp("bom.ini", "\xEF\xBB\xBF[matcher]\niterations = 5\n");
  EXPECT_EQ(LidarsegConfig::loadFile(bom).odometry.matcher.iterations, 5u);
  // A tab in a YAML indentation: one line naming the file and line (the parser printed three
  // lines naming "<memory-@0x...>").
  const std::string tab = writeTemp("tab.yaml", "matcher:\n\titerations: 3\n");
  EXPECT_EQ(errorOf(tab), tab + ":2: a tab in the indentation (YAML indents with spaces only)");
  // The same checks hold for a tool reading one section (lidarseg-segment --section).
  EXPECT_THROW(loadSegmentationParamsFile(stray, "matcher"), std::invalid_argument);
  // An INI section given twice with different keys is merged, as before.
  const std::string merged = writeTemp("merged.ini", "[matcher]\niterations = 3\n[odometry]\n[matcher]\nmax_segments = 64\n");
  const LidarsegConfig c = LidarsegConfig::loadFile(merged);
  EXPECT_EQ(c.odometry.matcher.iterations, 3u);
  EXPECT_EQ(c.odometry.matcher.max_segments, 64u);
}

// Issue 16 (a reliability attack's findings): lines the parsers would skip or documents they
// would ignore are errors naming file:line, not a run on the defaults.
TEST(LidarsegConfig, LinesAndDocumentsAParserWouldIgnoreAreErrorsNamingFileAndLine) {
  const std::string no_equals = writeTemp("noequals.ini", "[matcher]\n; fine\niterations 1000000000\n");
  EXPECT_EQ(errorOf(no_equals), no_equals + ":3: 'iterations 1000000000' is not a 'key = value' line (nor a "
                                            "[section], a comment or blank)");
  const std::string yaml_as_ini = writeTemp("yamlini.ini", "segmentation:\n  wd_threshold_m: 0.5\n");
  EXPECT_EQ(errorOf(yaml_as_ini).rfind(yaml_as_ini + ":1: 'segmentation:' is not a 'key = value' line", 0), 0u)
      << errorOf(yaml_as_ini);
  // MRPT skips every '@' line but '@define': an '@include' read nothing.
  const std::string include = writeTemp("include.ini", "@include other.ini\n[segmentation]\nwd_min_points = 3\n");
  EXPECT_EQ(errorOf(include), include + ":1: '@include other.ini' is no directive the INI reader knows (only "
                                        "'@define NAME VALUE'); it would be skipped (there is no '@include': give "
                                        "one file)");
  const std::string define = writeTemp("define.ini", "@define POINTS 4\n[segmentation]\nwd_min_points = ${POINTS}\n");
  EXPECT_EQ(LidarsegConfig::loadFile(define).odometry.segmentation.wall_danielsson.min_points, 4u);
  const std::string open_section = writeTemp("opensection.ini", "[matcher\niterations = 3\n");
  EXPECT_EQ(errorOf(open_section), open_section + ":1: '[matcher' opens a section without closing it ('[name]')");
  const std::string two_docs =
      writeTemp("twodocs.yaml", "---\nsegmentation:\n  wd_threshold_m: 0.05\n---\nmatcher:\n  iterations: 1000000000\n");
  EXPECT_EQ(errorOf(two_docs),
            two_docs + ":4: a second YAML document (or a document end '...'); a parameter file holds one");
  const std::string doc_end = writeTemp("docend.yaml", "segmentation:\n  wd_threshold_m: 0.05\n...\nmatcher: 3\n");
  EXPECT_EQ(errorOf(doc_end).rfind(doc_end + ":3: a second YAML document", 0), 0u) << errorOf(doc_end);
  // One document with its start marker is fine.
  const std::string one_doc = writeTemp("onedoc.yaml", "# a comment\n---\nmatcher:\n  iterations: 3\n");
  EXPECT_EQ(LidarsegConfig::loadFile(one_doc).odometry.matcher.iterations, 3u);
}

// Issue 16 (decision 84's gap): a key given twice inside a YAML flow mapping was kept
// silently by the parser (the last value won); it is an error naming file:line and key,
// compared without case as in block mappings, on one line or over several.
TEST(LidarsegConfig, DuplicateKeysInYamlFlowMappingsAreErrorsNamingFileLineAndKey) {
  const std::string one_line = writeTemp("flowtwice.yaml", "odometry:\n  keyframe_distance_m: 0.2\nmatcher: {iterations: 3, iterations: 4}\n");
  EXPECT_EQ(errorOf(one_line), one_line + ":3 [matcher] iterations: given twice in a flow mapping (first at line 3); "
                                          "the parser would keep only the last");
  const std::string cased = writeTemp("flowcase.yaml", "matcher: {iterations: 3, max_segments: 64, Iterations: 400}\n");
  EXPECT_EQ(errorOf(cased).rfind(cased + ":1 [matcher] Iterations: given twice in a flow mapping (first at line 1)", 0),
            0u)
      << errorOf(cased);
  const std::string lines = writeTemp("flowlines.yaml", "matcher: {\n  iterations: 3,\n  \"max_segments\": 64,\n"
                                                        "  'iterations': 5\n}\n");
  // Over several lines the keys stand one per line: found by either check, with the same lines.
  EXPECT_EQ(errorOf(lines).rfind(lines + ":4 [matcher] iterations: given twice", 0), 0u) << errorOf(lines);
  EXPECT_NE(errorOf(lines).find("(first at line 2)"), std::string::npos) << errorOf(lines);
  const std::string nested = writeTemp("flownested.yaml", "matcher: {\n  iterations: 3, max_segments: 64,\n"
                                                          "  Max_Segments: 65}\n");
  EXPECT_EQ(errorOf(nested).rfind(nested + ":3 [matcher] Max_Segments: given twice in a flow mapping (first at line 2)", 0),
            0u)
      << errorOf(nested);
  const std::string document = writeTemp("flowdoc.yaml", "{matcher: {iterations: 3}, odometry: {}, Matcher: {iterations: 4}}\n");
  EXPECT_EQ(errorOf(document).rfind(document + ":1: key 'Matcher': given twice in a flow mapping (first at line 1)", 0),
            0u)
      << errorOf(document);
  // Equal keys in different mappings, and equal values, are fine; the flow mapping is read.
  const std::string fine = writeTemp("flowfine.yaml", "matcher: {iterations: 3, max_segments: 64}\n"
                                                      "odometry: {matcher: {iterations: 5}, keyframe_distance_m: 0.2}\n");
  const std::string e = errorOf(fine);
  EXPECT_EQ(e.find("given twice"), std::string::npos) << e;
  const std::string plain = writeTemp("flowplain.yaml", "matcher: {iterations: 7, max_segments: 64}\n");
  const LidarsegConfig c = LidarsegConfig::loadFile(plain);
  EXPECT_EQ(c.odometry.matcher.iterations, 7u);
  EXPECT_EQ(c.odometry.matcher.max_segments, 64u);
}

// Issue 16: an alias or an empty section made MRPT's YAML parser fail with its banner and an
// assertion ("==== MRPT exception ====", "nVal.has_value()").
TEST(LidarsegConfig, YamlAliasesAndEmptySectionsGetOneLineNamingFileAndLine) {
  const std::string alias = writeTemp("alias.yaml", "matcher:\n  iterations: &n 3\n  min_matches: *n\n");
  EXPECT_EQ(errorOf(alias), alias + ":2: YAML anchors and aliases ('&name', '*name') are not supported in a "
                                    "parameter file");
  const std::string empty = writeTemp("empty.yaml", "segmentation:\nmatcher:\n  iterations: 2\n");
  EXPECT_EQ(errorOf(empty), empty + ":1 [segmentation]: the section is empty (a section maps keys to values)");
  const std::string last = writeTemp("emptylast.yaml", "matcher:\n  iterations: 2\nodometry:   # nothing\n");
  EXPECT_EQ(errorOf(last), last + ":3 [odometry]: the section is empty (a section maps keys to values)");
  const std::string novalue = writeTemp("novalue.yaml", "matcher:\n  iterations:\n  min_matches: 3\n");
  EXPECT_EQ(errorOf(novalue), novalue + ":2 [matcher] iterations: no value");
  // Whatever else MRPT's parser refuses is one line without its banner.
  const std::string broken = writeTemp("broken.yaml", "matcher:\n  iterations: \"2\n");
  const std::string e = errorOf(broken);
  EXPECT_EQ(e.rfind(broken + ": not valid YAML: ", 0), 0u) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  EXPECT_EQ(e.find("MRPT exception"), std::string::npos) << e;
  EXPECT_EQ(e.find("nVal"), std::string::npos) << e;
  // A '#' inside a quoted value is not a comment; a nested map is not an empty value.
  const std::string quoted = writeTemp("quoted.yaml", "odometry:\n  level: \"fused # x\"\n");
  EXPECT_NE(errorOf(quoted).find("is not one of"), std::string::npos) << errorOf(quoted);
}

// Issue 16: a subnormal value was "not a number".
TEST(LidarsegConfig, ANumberTooSmallOrLargeForADoubleIsOutOfRange) {
  for (const char* text : {"1e-320", "1e-400", "1e400", "-1e999"}) {
    const std::string path = writeTemp("tiny.ini", std::string("[segmentation]\nwd_threshold_m = ") + text + "\n");
    EXPECT_EQ(errorOf(path), path + ":2 [segmentation] wd_threshold_m: '" + text +
                                 "' is out of range (a magnitude from 2.2e-308 to 1.8e308, or 0)");
  }
  const std::string zero = writeTemp("zero.ini", "[segmentation]\nwd_threshold_m = 0\n");
  EXPECT_NE(errorOf(zero).find("wd_threshold_m must be finite and > 0"), std::string::npos) << errorOf(zero);
  const std::string word = writeTemp("word.ini", "[segmentation]\nwd_threshold_m = abc\n");
  EXPECT_NE(errorOf(word).find("'abc' is not a number"), std::string::npos) << errorOf(word);
  // A hexadecimal float, which strtod reads (as 0.5 here), is no number of a config file.
  const std::string hex = writeTemp("hex.ini", "[segmentation]\nwd_threshold_m = 0x1p-1\n");
  EXPECT_NE(errorOf(hex).find(":2 [segmentation] wd_threshold_m: '0x1p-1' is not a number"), std::string::npos)
      << errorOf(hex);
}

// Issue 16: counts that drive the work are bounded in every section (the search's rotation
// step, the matcher's and refiner's iterations), named with file and line.
TEST(LidarsegConfig, UnboundedCountsAreRefusedWithFileLineAndKey) {
  const std::string step = writeTemp("step.ini", "[search]\nangular_step_rad = 1e-12\n");
  EXPECT_EQ(errorOf(step).rfind(step + ":2 [search] angular_step_rad: angular_step_rad must be 0 (automatic) or in "
                                       "[0.0005, 0.5]",
                                0),
            0u)
      << errorOf(step);
  const std::string matcher = writeTemp("iters.ini", "[matcher]\niterations = 1000000000\n");
  EXPECT_EQ(errorOf(matcher).rfind(matcher + ":2 [matcher] iterations: iterations must be <= 1000", 0), 0u)
      << errorOf(matcher);
  const std::string refiner = writeTemp("refiter.ini", "[refiner]\nmax_iterations = 1000000000\n");
  EXPECT_EQ(errorOf(refiner).rfind(refiner + ":2 [refiner] max_iterations: max_iterations must be in [1, 1000]", 0),
            0u)
      << errorOf(refiner);
}

// Issue 16: `start_time_s = 1e16` gave identical stamps, `num_beams = 100000000` a bare
// std::bad_alloc.
TEST(LidarsegConfig, SimulationStampsAndSizesAreBoundedWithTheKeyNamed) {
  const auto simError = [](const std::string& body) {
    const std::string path = writeTemp("sim.ini", "[simulation]\n" + body + "\n");
    try {
      sim::SimulationParams p;
      loadSimulationParamsFile(p, path);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what()).substr(path.size());
    }
    return std::string("no error");
  };
  EXPECT_EQ(simError("start_time_s = 1e16").rfind(":2 [simulation] start_time_s: start_time_s must be finite and in "
                                                  "[-9e9, 9e9] s",
                                                  0),
            0u)
      << simError("start_time_s = 1e16");
  // Below the sensor's minimum range the scans' own check failed later, naming no file or key.
  EXPECT_EQ(simError("max_range_m = 1e-3"),
            ":2 [simulation] max_range_m: max_range_m must be greater than the sensor's minimum range, 0.05 m (got "
            "0.001)");
  EXPECT_EQ(simError("num_beams = 100000000").rfind(":2 [simulation] num_beams: num_beams must be 0 (profile) or in "
                                                    "[2, 100000]",
                                                    0),
            0u)
      << simError("num_beams = 100000000");
  EXPECT_EQ(simError("camera_width = 100000").rfind(":2 [simulation] camera_width: camera_width must be in [16, 8192]",
                                                    0),
            0u)
      << simError("camera_width = 100000");
  EXPECT_EQ(simError("start_time_s = 1767225600\nnum_beams = 100000"), "no error");
  // Magnitudes no robot, camera or noise model has reached the simulated odometry as 300-digit
  // numbers (issue 16).
  EXPECT_EQ(simError("odom_translation_per_m = 1e200"),
            ":2 [simulation] odom_translation_per_m: odom_translation_per_m must be within +-10 (m per m) (got 1e+200)");
  for (const char* key : {"odom_rotation_per_rad", "range_sigma_m", "far_range_sigma_m", "camera_x_m", "camera_cx",
                          "camera_yaw_rad"}) {
    const std::string e = simError(std::string(key) + " = 1e308");
    EXPECT_EQ(e.rfind(":2 [simulation] " + std::string(key) + ": " + key + " must be within +-", 0), 0u) << e;
  }
  // A scan rate of 1e-300 Hz wrote 300-digit stamps (issue 16): 0.1 to 1000 Hz.
  for (const char* v : {"1e-300", "0.01", "1e6"}) {
    EXPECT_EQ(simError(std::string("frequency_hz = ") + v).rfind(":2 [simulation] frequency_hz: frequency_hz must be in "
                                                                 "[0.1, 1000] Hz",
                                                                 0),
              0u)
        << simError(std::string("frequency_hz = ") + v);
  }
  EXPECT_EQ(simError("frequency_hz = 0.1"), "no error");
  EXPECT_EQ(simError("frequency_hz = 1000"), "no error");
}

// An output stamp nudge of 1e308 s wrote inf stamps, 1e-12 s nudged nothing (issue 16).
TEST(LidarsegConfig, TheOutputStampNudgeIsBounded) {
  for (const char* v : {"1e308", "1e-12", "2"}) {
    const std::string e = errorOf(writeTemp("nudge.ini", std::string("[stamps]\noutput_nudge_s = ") + v + "\n"));
    EXPECT_NE(e.find(":2 [stamps] output_nudge_s"), std::string::npos) << v << ": " << e;
    EXPECT_NE(e.find("in [1e-06, 1]"), std::string::npos) << v << ": " << e;
  }
  EXPECT_EQ(errorOf(writeTemp("nudge.ini", "[stamps]\noutput_nudge_s = 1e-6\n")), "");
}

// Issue 16: a noise model's standard deviation of 1e100 m reached results.md as a 100-digit
// final sigma, 1e200 as "-nan" (its square overflowed); every sigma is bounded.
TEST(LidarsegConfig, StandardDeviationsAreBoundedWithTheKeyNamed) {
  const auto errorFor = [](const std::string& section, const std::string& line) {
    return errorOf(writeTemp("sigma.ini", "[" + section + "]\n" + line + "\n"));
  };
  for (const auto& [section, key] : std::vector<std::pair<std::string, std::string>>{
           {"refiner", "model_sigma_m"}, {"refiner", "min_point_sigma_m"}, {"refiner", "model_sigma_rad"},
           {"segmentation", "bearing_sigma_rad"}, {"segmentation", "range_sigma_m"}, {"matcher", "min_rho_sigma_m"}}) {
    const std::string e = errorFor(section, key + " = 1e100");
    EXPECT_NE(e.find(":2 [" + section + "] " + key + ": "), std::string::npos) << e;
    EXPECT_NE(e.find(key + " must be in "), std::string::npos) << e;
    EXPECT_EQ(errorFor(section, key + " = 0.01").find(key), std::string::npos) << section << " " << key;
  }
}

}  // namespace
}  // namespace lidarseg::mrpt_adapter
