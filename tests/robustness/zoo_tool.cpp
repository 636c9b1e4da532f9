// SPDX-License-Identifier: GPL-3.0-or-later
// Helper of meshlabserver_zoo.sh: writes the plugin subset of the defect zoo
// as files, and checks what meshlabserver wrote back.
//
//   sodt_zoo_tool write DIR         writes DIR/<name>.ply (binary, float
//                                   coordinates, as MeshLab stores them) or
//                                   DIR/<name>.off (polygons) for every zoo
//                                   mesh of the plugin subset, and prints
//                                   "<name> <file>" lines
//   sodt_zoo_tool write-one NAME FILE  writes one zoo mesh (any) to FILE
//   sodt_zoo_tool expect NAME       prints the plugin log's count phrase the
//                                   zoo expects: "fixed B boundary and N
//                                   non-manifold vertices"
//   sodt_zoo_tool check NAME OUT    loads OUT with the project's loader and
//                                   prints one line; exit 0 when OUT is
//                                   readable and finite and, if it has the
//                                   zoo mesh's vertex count, every vertex the
//                                   zoo expects fixed kept its float bits;
//                                   exit 1 otherwise
#include "defect_zoo.h"
#include "zoo_checks.h"

#include <sodt_io/io.h>

#include <cstdio>
#include <cstring>
#include <string>

namespace {

int usage() {
  std::fprintf(stderr,
               "usage: sodt_zoo_tool write DIR | write-one NAME FILE | expect NAME | check NAME OUT\n");
  return 2;
}

void writeOne(const sodt_zoo::ZooMesh& z, const std::string& file) {
  if (!z.offText.empty())
    sodt_zoo::writeText(file, z.offText);
  else
    sodt_zoo::writePly(file, z.soup, sodt_zoo::PlyEncoding::BinaryLE, false);
}

int check(const std::string& name, const std::string& out) {
  const sodt_zoo::ZooMesh z = sodt_zoo::zooMesh(name);
  sodt::MeshF m;
  try {
    sodt::loadMesh(out, m);
  } catch (const std::exception& e) {
    std::printf("%s: output unreadable or not finite: %s\n", name.c_str(), e.what());
    return 1;
  }
  if (!sodt_zoo::allFinite(m)) {
    std::printf("%s: non-finite output coordinate\n", name.c_str());
    return 1;
  }
  sodt::MeshF in;
  sodt_zoo::toMesh(z.soup, in);
  std::printf("%s: vertices %d -> %d, faces %d -> %d", name.c_str(), in.vn, m.vn, in.fn, m.fn);
  if (m.vn != in.vn || z.kind.size() != static_cast<std::size_t>(in.vn)) {
    std::printf("; MeshLab changed the vertex list, fixed vertices not compared\n");
    return 0;
  }
  int fixed = 0, kept = 0, moved = 0;
  for (std::size_t i = 0; i < z.kind.size(); ++i) {
    const bool same = sodt_zoo::sameBits<sodt::MeshF>(in.vert[i].cP(), m.vert[i].cP());
    if (z.kind[i] == sodt_zoo::Kind::Interior) {
      moved += !same;
    } else {
      ++fixed;
      kept += same;
    }
  }
  std::printf("; fixed vertices kept %d/%d; interior vertices moved %d/%d\n", kept, fixed, moved,
              z.count(sodt_zoo::Kind::Interior));
  return kept == fixed ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc == 3 && std::strcmp(argv[1], "write") == 0) {
      for (const sodt_zoo::ZooMesh& z : sodt_zoo::makeZoo()) {
        if (!z.plugin) continue;
        const std::string file = std::string(argv[2]) + "/" + z.name + (z.offText.empty() ? ".ply" : ".off");
        writeOne(z, file);
        std::printf("%s %s\n", z.name.c_str(), file.c_str());
      }
      return 0;
    }
    if (argc == 4 && std::strcmp(argv[1], "write-one") == 0) {
      writeOne(sodt_zoo::zooMesh(argv[2]), argv[3]);
      return 0;
    }
    if (argc == 3 && std::strcmp(argv[1], "expect") == 0) {
      const sodt_zoo::ZooMesh z = sodt_zoo::zooMesh(argv[2]);
      std::printf("fixed %d boundary and %d non-manifold vertices\n", z.count(sodt_zoo::Kind::Boundary),
                  z.count(sodt_zoo::Kind::NonManifold));
      return 0;
    }
    if (argc == 4 && std::strcmp(argv[1], "check") == 0) return check(argv[2], argv[3]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sodt_zoo_tool: %s\n", e.what());
    return 1;
  }
  return usage();
}
