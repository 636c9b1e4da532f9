// SPDX-License-Identifier: GPL-3.0-or-later
// A main() for fuzz_mesh.cpp without libFuzzer: runs the target once on each
// file given (a directory stands for the files directly in it, README* and
// *.md excepted), so the regression inputs can run in any build (gcc, the
// sanitizer build, plain Release) as an ordinary test:
//
//   sodt_fuzz_replay fuzz/regressions
//
// A finding aborts (or crashes, or hangs: give the test a timeout); otherwise
// every file prints "ok" and the exit status is 0.
#include <dirent.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv);
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

bool isDir(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

void collect(const std::string& arg, std::vector<std::string>& files) {
  if (!isDir(arg)) {
    files.push_back(arg);
    return;
  }
  DIR* d = ::opendir(arg.c_str());
  if (!d) return;
  std::vector<std::string> found;
  while (const dirent* e = ::readdir(d)) {
    const std::string name = e->d_name;
    if (name.empty() || name[0] == '.' || name.rfind("README", 0) == 0) continue;
    if (name.size() > 3 && name.compare(name.size() - 3, 3, ".md") == 0) continue;
    const std::string path = arg + "/" + name;
    if (!isDir(path)) found.push_back(path);
  }
  ::closedir(d);
  std::sort(found.begin(), found.end());
  files.insert(files.end(), found.begin(), found.end());
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) collect(argv[i], files);
  if (files.empty()) {
    std::fprintf(stderr, "usage: %s FILE|DIR...\n", argv[0]);
    return 2;
  }
  LLVMFuzzerInitialize(&argc, &argv);
  for (const std::string& f : files) {
    std::ifstream in(f, std::ios::binary);
    if (!in) {
      std::fprintf(stderr, "cannot read %s\n", f.c_str());
      return 2;
    }
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::printf("running %s\n", f.c_str());
    std::fflush(stdout);
    LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
    std::printf("ok %s\n", f.c_str());
    std::fflush(stdout);
  }
  return 0;
}
