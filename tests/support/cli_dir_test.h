#pragma once
// The fixture of the CLI tests: a fresh directory per test (named by the test, removed after it),
// the built `thicket` run in it, and the files it reads and writes there.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "support/cli_run.h"

namespace thicket::testing {

class CliDirTest : public ::testing::Test {
protected:
    /// Skips when the tool was not built (the ctest entry then shows as skipped, which CI refuses).
    void SetUp() override {
        if (std::string(THICKET_CLI).empty()) GTEST_SKIP() << "the thicket executable was not built";
        dir_ = std::filesystem::temp_directory_path() /
               ("thicket_cli_" + std::to_string(getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name() + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::remove_all(dir_);
        std::filesystem::create_directories(dir_);
    }
    void TearDown() override {
        if (!dir_.empty()) std::filesystem::remove_all(dir_);
    }

    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    /// path(name) quoted for the shell.
    std::string q(const std::string& name) const { return shell_quote(path(name)); }
    /// `thicket ARGS` in the test's directory.
    CliResult run(const std::string& args) const { return run_thicket(args, dir_.string()); }
    /// The same under an address-space limit of `kib` KiB (`ulimit -v`), so that an allocation a
    /// memory check misses fails at once (std::bad_alloc) instead of taking the machine's memory.
    CliResult run_limited(const std::string& args, long kib) const {
        return run_thicket(args, dir_.string(), "", "ulimit -v " + std::to_string(kib) + ";");
    }
    std::string read(const std::string& name) const {
        std::ifstream in(path(name), std::ios::binary);
        return {std::istreambuf_iterator<char>(in), {}};
    }
    void write(const std::string& name, const std::string& bytes) const {
        std::ofstream(path(name), std::ios::binary) << bytes;
    }
    /// Exit code `code` (1: an error of ours, 2: a usage error from the option parser), every
    /// fragment in the output, and never a bare bad_alloc.
    static void expect_refused(const CliResult& r, const std::vector<std::string>& fragments, int code = 1) {
        EXPECT_EQ(r.code, code) << r.output;
        for (const std::string& f : fragments)
            EXPECT_NE(r.output.find(f), std::string::npos) << f << " not in: " << r.output;
        EXPECT_EQ(r.output.find("bad_alloc"), std::string::npos) << r.output;
    }

    std::filesystem::path dir_;
};

}  // namespace thicket::testing
