// SPDX-License-Identifier: GPL-3.0-or-later
// Mesh file I/O for the CLI, the tests and the benchmarks: PLY and OFF by
// extension, strict input checks, and output files replaced atomically.
#pragma once

#include "mesh.h"
#include <sodt/params.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace sodt {

/// Thrown when an output file cannot be written. Reading errors throw
/// InvalidInput instead (see loadMesh).
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Mesh file formats the project reads and writes.
enum class MeshFormat { Ply, Off, Obj, Stl };

/// Format of a path from its extension, case-insensitive (.ply, .off, .obj, .stl).
/// \throw InvalidInput naming the path for any other extension.
MeshFormat meshFormatFromPath(const std::string& path);

/// What saveMesh writes besides positions and triangles. A format without a
/// place for something asked for leaves it out (notKept() names it).
struct SaveOptions {
  bool binary = true;            ///< PLY only: binary little-endian instead of ASCII
  bool vertexQuality = false;    ///< PLY only: per-vertex "quality" (float)
  bool vertexColor = false;      ///< PLY and OFF: per-vertex RGBA colour
  bool vertexSelection = false;  ///< PLY only: per-vertex "flags" holding only the selection bit
  bool vertexNormals = false;    ///< PLY (nx, ny, nz) and OBJ (vn): the mesh's vertex normals
  /// PLY (texture_u, texture_v, and the mesh's texture files as "TextureFile"
  /// comments), OFF (ST prefix) and OBJ (vt): per-vertex texture coordinates
  bool vertexTexCoords = false;
  bool verify = true;            ///< read the written file back and compare counts before committing
};

/// What loadMesh found in the file besides positions and triangles.
struct LoadInfo {
  bool vertexQuality = false;    ///< the file has per-vertex quality
  bool vertexColor = false;      ///< the file has per-vertex colour
  bool vertexSelection = false;  ///< the file has per-vertex flags (PLY "flags")
  long long selectedVertices = 0;  ///< vertices whose selection bit is set
  bool polygons = false;         ///< faces with more than three corners were fan-triangulated
  long long weldedCorners = 0;   ///< STL: corners merged into a vertex with the same coordinates
  /// The file has vertex normals (PLY nx/ny/nz, OFF N prefix, OBJ vn). The
  /// mesh holds normals computed from its faces instead (a vertex no face
  /// uses keeps a normal read from a PLY or OFF file).
  bool vertexNormals = false;
  bool vertexTexCoords = false;  ///< per-vertex texture coordinates were read into the mesh
  /// What the file holds that the mesh does not keep, one item each, e.g.
  /// "vertex property 'myattr'", "face properties 'red', 'green', 'blue'",
  /// "OBJ statements 'mtllib', 'usemtl'".
  std::vector<std::string> dropped;
};

/// Reads a triangle mesh from a .ply, .off, .obj or .stl file into m (m is
/// cleared first).
///
/// PLY is read with vcglib's importer; polygons are fan-triangulated. Per-vertex
/// quality, colour, normals and texture coordinates (s/t or texture_u/texture_v)
/// and "TextureFile" comments (m.textures) are read when present; of a PLY
/// "flags" property only the selection bit is kept, so a file saved with
/// selection flags (MeshLab "flags" option) drives SodtParams::selectedOnly.
/// OFF is read by a strict parser of this file (vcglib 2020.09's OFF importer
/// does not range-check face indices); N/C/ST prefixes are accepted, COFF
/// vertex colours (3 or 4 values, 0..255 or 0..1), normals and texture
/// coordinates are read, face colours skipped, polygons fan-triangulated.
/// OBJ: 'v', 'vt', 'vn' and 'f' statements (i, i/t, i//n, i/t/n corners,
/// negative indices, polygons); texture coordinates are kept when every
/// vertex has one pair in all its corners; all else is ignored (and listed in
/// LoadInfo::dropped). STL: binary or ASCII (keywords in any case); corners
/// with equal coordinates are welded into one vertex
/// (LoadInfo::weldedCorners). A UTF-8 byte-order mark at the start of a text
/// file (or of a PLY header) is skipped. A file with vertices but no faces
/// loads fine (callers decide whether that is an error). On return the mesh
/// is compact, its bounding box and normals (from the faces) are up to date.
///
/// \throw InvalidInput with a one-line message naming the file: missing or
///        unreadable file, unsupported extension, parse error
///        (with vcglib's error string for PLY), a face index out of range,
///        a non-finite coordinate (naming the vertex index), binary data in a
///        text format (a NUL byte in its first KB, a run of more than 4096
///        bytes without a space or line end, a PLY header line longer than
///        1 MiB).
/// \param info when not null, receives what the file carried besides geometry.
void loadMesh(const std::string& path, MeshD& m, LoadInfo* info = nullptr);
/// Single-precision overload of loadMesh(const std::string&, MeshD&, LoadInfo*).
void loadMesh(const std::string& path, MeshF& m, LoadInfo* info = nullptr);

/// A file that is written under a temporary name in the target's directory
/// and renamed over the target by commit(). Destroying it without commit()
/// removes the temporary file, so the target is either the old file or the
/// complete new one, never a partial write. The target is replaced, not
/// rewritten in place: an existing target must be writable, its permission
/// bits are kept (not its owner or hard links); a symbolic link is followed
/// (a dangling one is refused, as cp does). Temporary files that earlier
/// runs left behind for the same target (killed with SIGKILL) are removed.
/// A character device or a FIFO (/dev/null, a named pipe, /dev/stdout on a
/// pipe) is written directly instead (direct()); block devices, sockets and
/// other special files are refused.
class PendingFile {
 public:
  /// Creates the temporary file (empty). \throw IoError naming the target.
  explicit PendingFile(const std::string& target);
  ~PendingFile();
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;

  /// Path the caller writes to before commit() (the target itself when direct()).
  const std::string& tempPath() const { return temp_; }
  /// True when the target is a character device or a FIFO, written in place:
  /// nothing is renamed, read back or removed.
  bool direct() const { return direct_; }
  /// Path given to the constructor.
  const std::string& target() const { return target_; }
  /// Flushes the temporary file to disk and renames it over the target.
  /// \throw IoError naming the target; the temporary file is removed then.
  void commit();

 private:
  std::string target_;    ///< as given
  std::string resolved_;  ///< target with a final symbolic link followed
  std::string temp_;
  bool committed_ = false;
  bool direct_ = false;
};

/// Writes m into out.tempPath() in the format of out.target()'s extension,
/// without committing. Deleted elements are skipped. Positions: binary PLY
/// and OBJ exactly, OFF with 16 significant digits (vcglib's writer), STL in
/// single precision (binary STL has no other) and without a vertex list
/// (unreferenced vertices are not kept). What each format keeps of opt:
/// see SaveOptions and notKept().
/// \throw InvalidInput for an unsupported extension, IoError if writing fails
///        or, for STL, if rounding to single precision would merge vertices
///        (the message says how many).
void saveMesh(PendingFile& out, const MeshD& m, const SaveOptions& opt = SaveOptions());
/// Single-precision overload of saveMesh(PendingFile&, const MeshD&, const SaveOptions&).
void saveMesh(PendingFile& out, const MeshF& m, const SaveOptions& opt = SaveOptions());

/// Writes m to path (format by extension) atomically: a failure leaves an
/// existing file at path untouched and creates nothing.
/// \throw InvalidInput for an unsupported extension, IoError if writing fails.
void saveMesh(const std::string& path, const MeshD& m, const SaveOptions& opt = SaveOptions());
/// Single-precision overload of saveMesh(const std::string&, const MeshD&, const SaveOptions&).
void saveMesh(const std::string& path, const MeshF& m, const SaveOptions& opt = SaveOptions());

/// What a file named path (format by extension) written with opt leaves out
/// of m because the format has no place for it, one item each (e.g. "vertex
/// normals", "the texture file 'tex.png'", "3 unreferenced vertices"); empty
/// when it keeps everything opt asks for. \throw InvalidInput for an
/// unsupported extension.
std::vector<std::string> notKept(const std::string& path, const MeshD& m, const SaveOptions& opt);

/// Writes text into out.tempPath() without committing. \throw IoError.
void writeText(PendingFile& out, const std::string& text);

/// Writes text to path atomically (see PendingFile). \throw IoError.
void writeTextFile(const std::string& path, const std::string& text);

}  // namespace sodt
