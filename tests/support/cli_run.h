#pragma once
// Running the built `thicket` executable (THICKET_CLI) from a test: its exit code and everything
// it printed.
#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace thicket::testing {

struct CliResult {
    int code = -1;       ///< exit status; -1 if it did not exit normally
    std::string output;  ///< stdout and stderr together
};

/// `s` in single quotes for the shell.
inline std::string shell_quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

/// Runs `thicket ARGS` through the shell, in directory `dir` when one is given, with the
/// environment assignments `env` (e.g. "THICKET_ISA=sse", as the shell reads them) when given,
/// after the shell commands `before` (e.g. "ulimit -v 100000;") in a subshell of its own.
inline CliResult run_thicket(const std::string& args, const std::string& dir = "", const std::string& env = "",
                             const std::string& before = "") {
    CliResult r;
    const std::string tool = (env.empty() ? "" : env + " ") + shell_quote(THICKET_CLI) + " " + args;
    const std::string cmd = (dir.empty() ? "" : "cd " + shell_quote(dir) + " && ") +
                            (before.empty() ? tool : "(" + before + " " + tool + ")") + " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    if (!pipe) return r;
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) r.output.append(buf, n);
    const int status = pclose(pipe);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

}  // namespace thicket::testing
