#include "validate/verify_queries.hpp"

#include <chrono>

#include "libcd/narrow_phase/edge_edge_ccd.hpp"
#include "libcd/narrow_phase/vertex_face_ccd.hpp"
#include "validate/exact_ccd.hpp"

namespace snag::validate {

namespace {

using Clock = std::chrono::steady_clock;

enum class Answer { kNo, kYes, kUncertain };

const char* answer_name(Answer answer) {
  switch (answer) {
    case Answer::kNo: return "no";
    case Answer::kYes: return "yes";
    case Answer::kUncertain: return "uncertain";
  }
  return "?";
}

std::array<RationalVec3, 8> rational_points(const io::CcdQuery& query) {
  std::array<RationalVec3, 8> points;
  for (std::size_t i = 0; i < 8; ++i) {
    const auto& c = query.exact[i];
    auto text = [](const io::ExactCoordinate& x) { return x.numerator_text + "/" + x.denominator_text; };
    points[i] = {text(c[0]), text(c[1]), text(c[2])};
  }
  return points;
}

Answer exact_answer(const io::CcdQuery& query) {
  const std::array<RationalVec3, 8> points = rational_points(query);
  const ExactCcdResult result =
      query.is_edge_edge ? exact_edge_edge_ccd(points) : exact_vertex_face_ccd(points);
  return result.collides ? Answer::kYes : Answer::kNo;
}

Answer filter_answer(const io::CcdQuery& query) {
  const auto& p = query.points;
  const CcdSettings settings;  // snag-scan's defaults, thickness 0
  const CcdResult result = query.is_edge_edge
                               ? edge_edge_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings)
                               : vertex_face_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings);
  switch (result.answer) {
    case CcdAnswer::kNo: return Answer::kNo;
    case CcdAnswer::kYes: return Answer::kYes;
    case CcdAnswer::kUncertain: return Answer::kUncertain;
  }
  return Answer::kUncertain;
}

// Counts one answer; returns true when it is wrong (a false positive or negative).
bool count(QueryCounts& counts, bool truth, Answer answer) {
  ++counts.queries;
  counts.positives += truth;
  switch (answer) {
    case Answer::kYes:
      (truth ? counts.true_positives : counts.false_positives) += 1;
      return !truth;
    case Answer::kNo:
      counts.false_negatives += truth;
      return truth;
    case Answer::kUncertain:
      ++counts.uncertain;
      counts.uncertain_positives += truth;
      return false;
  }
  return false;
}

template <typename Method>
void run_method(const std::vector<io::CcdQuery>& queries, const char* name, Method method, QueryCounts& vf,
                QueryCounts& ee, std::vector<QueryDisagreement>& disagreements) {
  for (const io::CcdQuery& query : queries) {
    const auto start = Clock::now();
    const Answer answer = method(query);
    QueryCounts& counts = query.is_edge_edge ? ee : vf;
    counts.seconds += std::chrono::duration<double>(Clock::now() - start).count();
    if (count(counts, query.truth, answer)) {
      disagreements.push_back(
          {name, query.file, query.line, query.is_edge_edge, query.truth, answer_name(answer)});
    }
  }
}

}  // namespace

QueryEvaluation evaluate_ccd_queries(const std::vector<io::CcdQuery>& queries) {
  QueryEvaluation evaluation;
  run_method(queries, "exact", exact_answer, evaluation.exact_vf, evaluation.exact_ee, evaluation.disagreements);
  run_method(queries, "filter", filter_answer, evaluation.filter_vf, evaluation.filter_ee,
             evaluation.disagreements);
  return evaluation;
}

}  // namespace snag::validate
