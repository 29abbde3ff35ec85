#include "exporters/marked_ply.hpp"

#include <cassert>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "libcd/core/error.hpp"

namespace snag::exporters {

namespace {

void put_u32(std::string& bytes, std::uint32_t value) {
  for (int i = 0; i < 4; ++i) bytes += static_cast<char>((value >> (8 * i)) & 0xffu);
}

void put_float(std::string& bytes, double value) {
  const float f = static_cast<float>(value);
  std::uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  put_u32(bytes, bits);
}

void put_int(std::string& bytes, std::int32_t value) { put_u32(bytes, static_cast<std::uint32_t>(value)); }

// One HSV-to-RGB conversion at full value.
std::array<unsigned char, 3> hsv(double hue, double saturation) {
  const double h = hue * 6.0;
  const int sector = static_cast<int>(h) % 6;
  const double f = h - std::floor(h);
  const double p = 1 - saturation, q = 1 - saturation * f, t = 1 - saturation * (1 - f);
  double r = 0, g = 0, b = 0;
  switch (sector) {
    case 0: r = 1, g = t, b = p; break;
    case 1: r = q, g = 1, b = p; break;
    case 2: r = p, g = 1, b = t; break;
    case 3: r = p, g = q, b = 1; break;
    case 4: r = t, g = p, b = 1; break;
    default: r = 1, g = p, b = q; break;
  }
  auto byte = [](double c) { return static_cast<unsigned char>(std::lround(c * 255.0)); };
  return {byte(r), byte(g), byte(b)};
}

}  // namespace

std::array<unsigned char, 3> region_colour(std::size_t id) {
  constexpr double kGoldenAngle = 0.381966011250105;  // of a turn
  const double hue = std::fmod(static_cast<double>(id % 100000) * kGoldenAngle, 1.0);
  const double saturation = id % 2 == 0 ? 0.85 : 0.65;
  return hsv(hue, saturation);
}

std::vector<std::size_t> face_regions(const ReportDigest& digest, const Scene& scene, std::size_t frame) {
  std::vector<std::size_t> regions(scene.triangle_count(), report::kNone);
  auto mark = [&](std::size_t object, const std::vector<std::size_t>& faces, std::size_t id) {
    if (object >= scene.objects().size()) return;
    const std::size_t offset = scene.triangle_offset(object);
    const std::size_t count = scene.objects()[object].triangles.size();
    for (std::size_t f : faces) {
      if (f >= count) {
        throw InputError(InputLocation{digest.path}, "region " + std::to_string(id) + " names face " +
                                                         std::to_string(f) + " of '" +
                                                         scene.objects()[object].name + "', which has " +
                                                         std::to_string(count));
      }
      std::size_t& r = regions[offset + f];
      if (r == report::kNone || id < r) r = id;
    }
  };
  for (const report::RegionRecord& region : digest.regions) {
    if (region.frame != frame) continue;
    mark(region.object_a, region.faces_a, region.id);
    if (region.object_b != region.object_a) mark(region.object_b, region.faces_b, region.id);
  }
  return regions;
}

void write_marked_ply(std::ostream& out, const Scene& scene, const std::vector<Vec3>& positions,
                      const std::vector<std::size_t>& face_region, const std::string& comment) {
  assert(positions.size() == scene.vertex_count());
  assert(face_region.size() == scene.triangle_count());
  out << "ply\nformat binary_little_endian 1.0\ncomment written by snag-report\n";
  if (!comment.empty()) out << "comment " << comment << "\n";
  for (std::size_t o = 0; o < scene.objects().size(); ++o) {
    const Object& object = scene.objects()[o];
    out << "comment object " << object.name << " faces " << scene.triangle_offset(o) << " to "
        << scene.triangle_offset(o + 1) << " (exclusive), vertices " << scene.vertex_offset(o) << " to "
        << scene.vertex_offset(o + 1) << "\n";
  }
  out << "element vertex " << positions.size() << "\nproperty float x\nproperty float y\nproperty float z\n"
      << "element face " << scene.triangle_count() << "\nproperty list uchar int vertex_indices\n"
      << "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty int region\nend_header\n";

  std::string bytes;
  bytes.reserve(positions.size() * 12);
  for (const Vec3& p : positions) {
    put_float(bytes, p.x);
    put_float(bytes, p.y);
    put_float(bytes, p.z);
  }
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  bytes.clear();
  bytes.reserve(scene.triangle_count() * 20);
  const std::vector<Triangle>& triangles = scene.triangles();
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    bytes += static_cast<char>(3);
    for (int corner = 0; corner < 3; ++corner) put_int(bytes, static_cast<std::int32_t>(triangles[f][corner]));
    const std::size_t region = face_region[f];
    const std::array<unsigned char, 3> colour = region == report::kNone ? kUnmarkedColour : region_colour(region);
    for (unsigned char c : colour) bytes += static_cast<char>(c);
    put_int(bytes, region == report::kNone || region > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())
                       ? -1
                       : static_cast<std::int32_t>(region));
  }
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string marked_mesh_name(const ReportDigest& digest, std::size_t frame) {
  return report_stem(digest.path) + "_frame_" + std::to_string(frame) + ".ply";
}

}  // namespace snag::exporters
