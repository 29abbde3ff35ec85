#include "validate/exact_certifier.hpp"

#include "validate/exact_ccd.hpp"

namespace snag::validate {

namespace {

class ExactCertifier final : public Certifier {
 public:
  explicit ExactCertifier(double toi_width) : toi_width_(toi_width) {}

  ExactAnswer vertex_face(const std::array<Vec3, 8>& points, double thickness) const override {
    return to_answer(exact_vertex_face_ccd(points, thickness, toi_width_));
  }
  ExactAnswer edge_edge(const std::array<Vec3, 8>& points, double thickness) const override {
    return to_answer(exact_edge_edge_ccd(points, thickness, toi_width_));
  }

 private:
  static ExactAnswer to_answer(const ExactCcdResult& exact) { return {exact.collides, exact.toi_lo, exact.toi_hi}; }
  double toi_width_;
};

}  // namespace

std::unique_ptr<Certifier> make_exact_certifier(double toi_width) {
  return std::make_unique<ExactCertifier>(toi_width);
}

}  // namespace snag::validate
