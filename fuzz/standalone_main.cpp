// A driver for the fuzz targets when they are not built with libFuzzer (GCC,
// or any build without CMKIT_LIBFUZZER): replays corpus files and then runs
// seeded random mutations of them, so that every sanitizer build exercises
// the parsers with odd input (ctest runs it; see fuzz/CMakeLists.txt).
//
//   fuzz_map [--runs N] [--seed S] [--save-last FILE] CORPUS...
//
// CORPUS: files or folders of files. --runs: mutated inputs after the
// replay (default 0). --save-last: write each input to FILE before running
// it, so that a crash leaves the input behind.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_common.h"

namespace {

namespace fs = std::filesystem;

/// Tokens the mutator splices in: syntax of the three formats, and numbers
/// at the edges of float and int.
constexpr std::string_view kTokens[] = {"{",           "}",          "(",
                                        ")",           "\"",         "\n",
                                        " ",           "-",          "0",
                                        "-0",          "1e38",       "-1e38",
                                        "1e-45",       "3.4e39",     "nan",
                                        "inf",         "-inf",       "2147483647",
                                        "-2147483648", "4294967296", "999999999999",
                                        "0x7fffffff",  ".",          "1.5.5",
                                        "brushDef3",   "patchDef2",  "patchDef3",
                                        "brushDef",    "Version",    "CM",
                                        "vertices",    "edges",      "polygons",
                                        "brushes",     "nodes",      "collisionModel",
                                        "//",          "/*",         "*/",
                                        "trm=",        "start=",     "end=",
                                        "box:",        "cylinder:",  "cone:",
                                        "bone:",       "polygon:",   "point",
                                        "rotation=",   "mask=",      "model=",
                                        "origin=",     "axis=",      "depth=",
                                        "dir=",        ","};

struct Mutator {
  std::mt19937_64 rng;

  std::size_t below(std::size_t n) { return n ? std::size_t(rng() % n) : 0; }

  std::string mutate(std::string s) {
    const int edits = 1 + int(below(4));
    for (int i = 0; i < edits; ++i) {
      const std::size_t at = below(s.size() + 1);
      switch (below(7)) {
        case 0:  // flip a bit
          if (!s.empty()) s[below(s.size())] ^= char(1u << below(8));
          break;
        case 1:  // a random byte
          s.insert(s.begin() + std::ptrdiff_t(at), char(below(256)));
          break;
        case 2: {  // a token
          const std::string_view t = kTokens[below(std::size(kTokens))];
          s.insert(at, t);
          break;
        }
        case 3:  // delete a range
          if (!s.empty()) s.erase(at < s.size() ? at : s.size() - 1, 1 + below(32));
          break;
        case 4: {  // duplicate a range
          if (s.empty()) break;
          const std::size_t from = below(s.size());
          const std::string piece = s.substr(from, 1 + below(64));
          s.insert(below(s.size() + 1), piece);
          break;
        }
        case 5:  // truncate
          s.resize(below(s.size() + 1));
          break;
        default: {  // replace a number-looking run with a token
          if (s.empty()) break;
          std::size_t b = below(s.size());
          while (b < s.size() && !(s[b] >= '0' && s[b] <= '9')) ++b;
          std::size_t e = b;
          while (e < s.size() && ((s[e] >= '0' && s[e] <= '9') || s[e] == '.' || s[e] == 'e' || s[e] == '-'))
            ++e;
          s.replace(b, e - b, kTokens[below(std::size(kTokens))]);
          break;
        }
      }
    }
    if (s.size() > cmkit::fuzz::kMaxInputBytes) s.resize(cmkit::fuzz::kMaxInputBytes);
    return s;
  }
};

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

int usage(const char* argv0) {
  std::fprintf(stderr,
               "usage: %s [--runs N] [--seed S] [--save-last FILE] CORPUS...\n"
               "Replays every corpus file (files or folders), then runs N seeded random\n"
               "mutations of them through the fuzz target. Built without libFuzzer; with it\n"
               "(cmake --preset fuzz) the target takes libFuzzer's options instead.\n",
               argv0);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  long runs = 0;
  std::uint64_t seed = 1;
  std::string saveLast;
  std::vector<std::string> corpus;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    if ((a == "--runs" || a == "--seed" || a == "--save-last") && i + 1 < argc) {
      const char* v = argv[++i];
      if (a == "--runs") runs = std::strtol(v, nullptr, 10);
      if (a == "--seed") seed = std::strtoull(v, nullptr, 10);
      if (a == "--save-last") saveLast = v;
    } else if (a == "--help" || a == "-h" || a.starts_with("--")) {
      return usage(argv[0]);
    } else {
      corpus.emplace_back(a);
    }
  }
  std::vector<std::string> inputs;
  for (const std::string& c : corpus) {
    std::error_code ec;
    if (fs::is_directory(c, ec)) {
      std::vector<fs::path> files;
      for (const auto& entry : fs::directory_iterator(c))
        if (entry.is_regular_file()) files.push_back(entry.path());
      std::sort(files.begin(), files.end());  // the same order everywhere
      for (const fs::path& f : files) inputs.push_back(readFile(f));
    } else if (fs::is_regular_file(c, ec)) {
      inputs.push_back(readFile(c));
    } else {
      std::fprintf(stderr, "%s: no such corpus file or folder: %s\n", argv[0], c.c_str());
      return 2;
    }
  }
  if (inputs.empty()) return usage(argv[0]);

  auto run = [&](const std::string& input) {
    if (!saveLast.empty()) std::ofstream(saveLast, std::ios::binary) << input;
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(input.data()), input.size());
  };
  for (const std::string& input : inputs) run(input);
  Mutator mutator{std::mt19937_64(seed)};
  for (long i = 0; i < runs; ++i) run(mutator.mutate(inputs[mutator.below(inputs.size())]));
  std::printf("%s: %zu corpus inputs and %ld mutations (seed %llu) ran without a finding\n", argv[0],
              inputs.size(), runs, static_cast<unsigned long long>(seed));
  return 0;
}
