/// \file
/// \brief The `play --config` loader (app/cli/play_config.h): what it reads (bounded in size and
/// in the wait for a FIFO's writer) and how it applies and checks keys (with the
/// fuzzer's finds).

#include "play_config.h"

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "support/temp_dir.h"

namespace depthtouch::cli {
namespace {

namespace fs = std::filesystem;

bool noneGiven(const std::string &)
{
    return false;
}

TEST(PlayConfigTest, ReadsABoundedFileAndNeverBlocks)
{
    testing::TempDir tmp("dt-play-config-");
    std::string text;
    const fs::path good = tmp.dir() / "play.toml";
    std::ofstream(good) << "stiffness = 900\n";
    EXPECT_EQ(readPlayConfigFile(good.string(), text), "");
    EXPECT_EQ(text, "stiffness = 900\n");

    const fs::path fifo = tmp.dir() / "cfg.fifo";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const fs::path big = tmp.dir() / "big.toml";
    std::ofstream(big).put('#');
    fs::resize_file(big, kMaxPlayConfigBytes + 1);
    const std::pair<std::string, std::string> refused[] = {
        {tmp.dir().string(), "is a directory"},
        {"/dev/zero", "is larger than the limit"},
        {fifo.string(), "is a FIFO with no writer"}, // after kPlayConfigFifoWait
        {big.string(), "is larger than the limit"},
        {(tmp.dir() / "missing.toml").string(), "No such file"},
    };
    for (const auto &[path, why] : refused) {
        const std::string err = readPlayConfigFile(path, text);
        EXPECT_NE(err.find(why), std::string::npos) << path << ": " << err;
        EXPECT_EQ(err.find('\n'), std::string::npos);
    }
}

TEST(PlayConfigTest, AppliesKeysAndTheCommandLineWins)
{
    PlayOptions o;
    const std::string text = "display = \"kms\"\nstiffness = 1200\nloop = true\nrecord-crf = 30\n";
    EXPECT_EQ(applyPlayConfigText(text, "p.toml", noneGiven, o), "");
    EXPECT_EQ(o.display, "kms");
    EXPECT_EQ(o.stiffness, 1200.0);
    EXPECT_TRUE(o.loop);
    EXPECT_EQ(o.recordCrf, 30);

    PlayOptions given;
    EXPECT_EQ(applyPlayConfigText(text, "p.toml",
                                  [](const std::string &key) { return key == "display"; }, given),
              "");
    EXPECT_EQ(given.display, PlayOptions{}.display) << "the command line's value stays";
    EXPECT_EQ(given.stiffness, 1200.0);
}

TEST(PlayConfigTest, AWrongTypeIsAnErrorEvenWhenTheCommandLineGivesTheOption)
{
    PlayOptions o;
    const std::string err = applyPlayConfigText(
        "stiffness = \"hard\"\n", "p.toml", [](const std::string &) { return true; }, o);
    EXPECT_EQ(err, "--config 'p.toml': 'stiffness' has the wrong type or is out of range");
}

TEST(PlayConfigTest, CountsAreIntegersInRange)
{
    // 1e30 as a count was undefined behaviour inside toml++ (found by play_config_fuzz).
    for (const char *text : {"snapshot-every = 1e30\n", "mesh-step = -1\n",
                             "record-crf = 9223372036854775807\n", "mesh-step = 2.0\n"}) {
        PlayOptions o;
        EXPECT_NE(applyPlayConfigText(text, "p.toml", noneGiven, o).find("wrong type"),
                  std::string::npos)
            << text;
    }
}

TEST(PlayConfigTest, MessagesQuoteAtMost64BytesOnOneLine)
{
    PlayOptions o;
    const std::string hugeKey(1 << 20, 'k');
    std::string err = applyPlayConfigText(hugeKey + " = 1\n", "p.toml", noneGiven, o);
    EXPECT_LT(err.size(), 200u);
    EXPECT_NE(err.find("unknown key 'kkkk"), std::string::npos) << err.substr(0, 200);
    EXPECT_NE(err.find("...'"), std::string::npos);
    err = applyPlayConfigText("\"a\\nb\" = 1\n", "p.toml", noneGiven, o);
    EXPECT_EQ(err, "--config 'p.toml': unknown key 'a?b'");
    err = applyPlayConfigText("display = \"" + std::string(1 << 20, 'x') + "\n", "p.toml",
                              noneGiven, o);
    EXPECT_LT(err.size(), 400u) << "a TOML syntax error quotes a bounded excerpt";
    EXPECT_EQ(err.find('\n'), std::string::npos);
}

} // namespace
} // namespace depthtouch::cli
