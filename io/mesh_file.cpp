#include "io/mesh_file.hpp"

#include "io/obj_reader.hpp"
#include "io/ply_reader.hpp"
#include "io/reader_support.hpp"
#include "io/stl_reader.hpp"
#include "libcd/core/error.hpp"
#include "snag/config.hpp"

#if SNAG_HAVE_ASSIMP
#include "io/assimp_reader.hpp"
#endif

namespace snag::io {

bool is_native_mesh_extension(const std::string& extension) {
  return extension == "obj" || extension == "ply" || extension == "stl";
}

bool is_mesh_extension(const std::string& extension) {
  if (is_native_mesh_extension(extension)) return true;
#if SNAG_HAVE_ASSIMP
  return is_assimp_extension(extension);
#else
  return false;
#endif
}

MeshData read_mesh_file(const std::string& path) {
  const std::string extension = lower_extension(path);
  if (extension == "obj") return read_obj(path);
  if (extension == "ply") return read_ply(path);
  if (extension == "stl") return read_stl(path);
#if SNAG_HAVE_ASSIMP
  if (is_assimp_extension(extension)) return read_mesh_with_assimp(path);
  throw InputError({path}, "unknown mesh format '." + extension + "'");
#else
  throw InputError({path}, "unknown mesh format '." + extension +
                               "' (OBJ, PLY and STL are read; other formats need a build with SNAG_WITH_ASSIMP=ON)");
#endif
}

}  // namespace snag::io
