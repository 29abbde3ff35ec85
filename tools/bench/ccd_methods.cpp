#include "tools/bench/ccd_methods.hpp"

#include "libcd/narrow_phase/edge_edge_ccd.hpp"
#include "libcd/narrow_phase/vertex_face_ccd.hpp"
#include "tools/bench/provot_cubic_ccd.hpp"
#include "validate/exact_ccd.hpp"

namespace snag::bench {

namespace {

CcdVerdict from_bool(bool collides) { return collides ? CcdVerdict::kYes : CcdVerdict::kNo; }

CcdAnswer filter_answer(const CcdQueryPoints& query) {
  const auto& p = query.points;
  const CcdSettings settings;  // snag-scan's defaults, thickness 0
  return (query.edge_edge ? edge_edge_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings)
                          : vertex_face_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings))
      .answer;
}

}  // namespace

const char* method_id(CcdMethod method) {
  switch (method) {
    case CcdMethod::kCubicFloat: return "cubic-float";
    case CcdMethod::kCubicDouble: return "cubic-double";
    case CcdMethod::kFilter: return "filter";
    case CcdMethod::kCertified: return "certified";
    case CcdMethod::kExact: return "exact";
  }
  return "?";
}

const char* method_label(CcdMethod method) {
  switch (method) {
    case CcdMethod::kCubicFloat: return "Provot cubic, float";
    case CcdMethod::kCubicDouble: return "Provot cubic, double";
    case CcdMethod::kFilter: return "snag filter alone (fast)";
    case CcdMethod::kCertified: return "snag filter + exact (default)";
    case CcdMethod::kExact: return "exact alone";
  }
  return "?";
}

bool exact_collides(const CcdQueryPoints& query) {
  return (query.edge_edge ? validate::exact_edge_edge_ccd(query.points) : validate::exact_vertex_face_ccd(query.points))
      .collides;
}

CcdVerdict run_ccd_method(CcdMethod method, const CcdQueryPoints& query) {
  switch (method) {
    case CcdMethod::kCubicFloat: return from_bool(provot_cubic_ccd<float>(query.points, query.edge_edge));
    case CcdMethod::kCubicDouble: return from_bool(provot_cubic_ccd<double>(query.points, query.edge_edge));
    case CcdMethod::kFilter:
      switch (filter_answer(query)) {
        case CcdAnswer::kNo: return CcdVerdict::kNo;
        case CcdAnswer::kYes: return CcdVerdict::kYes;
        case CcdAnswer::kUncertain: return CcdVerdict::kUncertain;
      }
      return CcdVerdict::kUncertain;
    case CcdMethod::kCertified: {
      const CcdAnswer answer = filter_answer(query);
      if (answer != CcdAnswer::kUncertain) return from_bool(answer == CcdAnswer::kYes);
      return from_bool(exact_collides(query));
    }
    case CcdMethod::kExact: return from_bool(exact_collides(query));
  }
  return CcdVerdict::kUncertain;
}

}  // namespace snag::bench
