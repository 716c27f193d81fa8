// A libFuzzer-compatible driver for builds without libFuzzer (gcc, the sanitizer job): runs the
// harness on every file of the given corpus directories, then on random mutations of them until
// -max_total_time=SECONDS (default 0: the corpus only) or -runs=N mutated inputs. No coverage
// feedback: this is the CI's bounded smoke run and regression replay, not a search. The real
// search is libFuzzer's (THICKET_FUZZ=ON with clang; docs/fuzzing.md).
#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

std::string read_file(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

/// Each input is written to last-input in the harness's scratch directory (tmpfs: a write per
/// input to a disk cost more than most harnesses) before it runs, and removed after a clean run:
/// when the harness crashes, aborts or a sanitizer ends the process, the file is the input to
/// reproduce it with and to keep as a regression (as libFuzzer writes crash-<sha1>).
const std::string& last_input() {
    static const std::string path = thicket::fuzz::scratch_dir() + "/last-input";
    return path;
}

void run(const std::string& input) {
    if (const int fd = ::open(last_input().c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644); fd >= 0) {
        (void)!::write(fd, input.data(), input.size());
        ::close(fd);
    }
    LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(input.data()), input.size());
}

/// One of libFuzzer's simple mutations: flip a bit, set a byte to an interesting value, insert,
/// erase, duplicate a chunk, or splice in a piece of another input.
std::string mutate(std::string s, const std::vector<std::string>& corpus, std::mt19937_64& rng, size_t max_len) {
    const int rounds = 1 + int(rng() % 4);
    for (int r = 0; r < rounds; ++r) {
        const size_t n = s.size();
        switch (rng() % 6) {
        case 0:
            if (n) s[rng() % n] ^= char(1u << (rng() % 8));
            break;
        case 1: {
            static const char special[] = {0, 1, '\x7f', '\x80', '\xff', '-', '9', ' ', '\n', '.'};
            if (n) s[rng() % n] = special[rng() % sizeof special];
            break;
        }
        case 2:
            s.insert(n ? rng() % n : 0, 1 + rng() % 8, char(rng()));
            break;
        case 3:
            if (n) s.erase(rng() % n, 1 + rng() % 16);
            break;
        case 4:
            if (n) {
                const size_t at = rng() % n, len = 1 + rng() % std::min<size_t>(64, n - at);
                s.insert(rng() % n, s.substr(at, len));
            }
            break;
        default: {
            const std::string& other = corpus[rng() % corpus.size()];
            if (!other.empty() && n) {
                const size_t at = rng() % other.size();
                s = s.substr(0, rng() % n) + other.substr(at, 1 + rng() % 64);
            }
        }
        }
    }
    if (s.size() > max_len) s.resize(max_len);
    return s;
}

}  // namespace

int main(int argc, char** argv) {
    double max_time = 0;
    long runs = -1;
    size_t max_len = 4096;
    std::vector<std::string> corpus;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a.rfind("-max_total_time=", 0) == 0) {
            max_time = std::atof(a.c_str() + 16);
        } else if (a.rfind("-runs=", 0) == 0) {
            runs = std::atol(a.c_str() + 6);
        } else if (a.rfind("-max_len=", 0) == 0) {
            max_len = size_t(std::atol(a.c_str() + 9));
        } else if (a.rfind("-", 0) == 0) {
            continue;  // other libFuzzer flags mean nothing here
        } else if (std::filesystem::is_directory(a)) {
            for (const auto& e : std::filesystem::directory_iterator(a))
                if (e.is_regular_file()) corpus.push_back(read_file(e.path()));
        } else if (std::filesystem::is_regular_file(a)) {
            corpus.push_back(read_file(a));
        }  // a corpus folder that does not exist (no regressions yet) adds nothing
    }
    if (corpus.empty()) corpus.push_back("");
    std::fprintf(stderr, "standalone fuzz driver: each input is written to %s before it runs\n", last_input().c_str());
    for (const std::string& input : corpus) run(input);
    std::mt19937_64 rng(16);
    const auto start = std::chrono::steady_clock::now();
    long done = 0;
    while (runs < 0 ? std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < max_time
                    : done < runs) {
        run(mutate(corpus[rng() % corpus.size()], corpus, rng, max_len));
        ++done;
    }
    std::printf("%zu corpus inputs and %ld mutations ran clean in %.1f s\n", corpus.size(), done,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return 0;
}
