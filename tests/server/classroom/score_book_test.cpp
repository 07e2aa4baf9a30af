// ScoreBook: what clients can make the server keep is bounded
// (docs/reliability.md, gap 8), and refusing more loses nothing already kept.
#include "hapsim/classroom/score_book.h"

#include <gtest/gtest.h>

#include "hapsim/runtime/errors.h"

namespace hapsim::service {
namespace {

const std::vector<double> kSheet = {5, 5, 5, 5, 5, 5, 5};

ErrorCode SubmitError(ScoreBook& book, const std::string& session, const std::string& expert) {
  try {
    book.Submit(session, "tissue_block", expert, kSheet);
  } catch (const ServiceError& e) {
    return e.code();
  }
  ADD_FAILURE() << "accepted " << session << "/" << expert;
  return ErrorCode::kInvalidArgument;
}

TEST(ScoreBook, ANewExpertBeyondTheLimitIsRefusedButEveryKeptExpertMayRescore) {
  ScoreBook book;
  for (std::size_t i = 0; i < ScoreBook::kMaxExpertsPerSession; ++i) {
    book.Submit("s", "tissue_block", "expert" + std::to_string(i), kSheet);
  }
  EXPECT_EQ(SubmitError(book, "s", "one-too-many"), ErrorCode::kResourceExhausted);
  EXPECT_NO_THROW(book.Submit("s", "tissue_block", "expert0", {9, 9, 9, 9, 9, 9, 9}));  // replacing is not growing
  const ScoreReport report = book.Report("s");
  ASSERT_EQ(report.sessions.size(), 1u);
  EXPECT_EQ(report.sessions[0].experts, ScoreBook::kMaxExpertsPerSession);
  // Mean of indicator 0 over 32 experts: one 9, thirty-one 5s.
  EXPECT_NEAR(report.sessions[0].mean_indicators[0], (9.0 + 31 * 5.0) / 32.0, 1e-12);
}

TEST(ScoreBook, ANewSessionBeyondTheLimitIsRefusedButKeptSessionsStillTakeSheets) {
  ScoreBook book;
  for (std::size_t i = 0; i < ScoreBook::kMaxScoredSessions; ++i) {
    std::string id = "s";  // (not "s" + to_string: GCC 12's -Wrestrict false positive)
    id += std::to_string(i);
    book.Submit(id, "tissue_block", "e", kSheet);
  }
  EXPECT_EQ(SubmitError(book, "one-too-many", "e"), ErrorCode::kResourceExhausted);
  EXPECT_NO_THROW(book.Submit("s0", "tissue_block", "another-expert", kSheet));
  const ScoreReport report = book.Report("");
  EXPECT_EQ(report.sessions.size(), ScoreBook::kMaxScoredSessions);
}

// The acupuncture paper's samples are one system's raters: two raters of one
// trainee, A = (8,6,7,9,5,8,7) and B = (6,6,9,9,7,8,5), give that trainee
// beta = (0.25,0,0.25,0,0.25,0,0.25) and f = mean(6.758, 6.822) = 6.790 (the
// hand-computed core example, ComprehensiveScore.MatchesHandComputedTwoTraineeExample).
// Another trainee's sheets, however wild, change nothing of it.
TEST(ScoreBook, ATraineesScoreDependsOnTheirOwnRatersOnly) {
  ScoreBook book;
  book.Submit("alice", "acupuncture", "dr-a", {8, 6, 7, 9, 5, 8, 7});
  book.Submit("alice", "acupuncture", "dr-b", {6, 6, 9, 9, 7, 8, 5});
  const ScoreReport alone = book.Report("alice");
  ASSERT_EQ(alone.sessions.size(), 1u);
  EXPECT_NEAR(alone.sessions[0].comprehensive_score, 6.790, 1e-12);
  EXPECT_NEAR(alone.combined_weights[0], 0.218, 1e-12);
  EXPECT_NEAR(alone.objective_weights[1], 0.0, 1e-12);
  EXPECT_EQ(alone.sessions[0].scheme, "delphi_msd");

  book.Submit("bob", "acupuncture", "dr-a", {0, 10, 0, 10, 0, 10, 0});
  book.Submit("bob", "acupuncture", "dr-b", {10, 0, 10, 0, 10, 0, 10});
  const ScoreReport with_bob = book.Report("alice");
  EXPECT_EQ(with_bob.sessions[0].comprehensive_score, alone.sessions[0].comprehensive_score);
  // What a viewer of alice may see.
  const ScoreReport cls = book.Report("", [](const std::string& id) { return id == "alice"; });
  ASSERT_EQ(cls.sessions.size(), 1u);
  EXPECT_EQ(cls.sessions[0].session_id, "alice");
}

// Cutting sessions use the cutting paper's fixed Delphi weights: two
// residents whose means are Table 3's "Ours" column (10,9,9,10,9,10,9) give
// the printed 9.43 (+-0.005, its rounding).
TEST(ScoreBook, CuttingSessionsUseTheResidentsWeightedScore) {
  ScoreBook book;
  book.Submit("c", "cutting", "r1", {10, 9, 9, 10, 9, 10, 9});
  book.Submit("c", "cutting", "r2", {10, 9, 9, 10, 9, 10, 9});
  const ScoreReport r = book.Report("c");
  EXPECT_EQ(r.sessions[0].scheme, "cutting_residents");
  EXPECT_NEAR(r.sessions[0].comprehensive_score, 9.43, 0.005);
  EXPECT_EQ(r.objective_weights.size(), 0u);
}

// Vessel sessions take 9 indicators weighted by the AHP hierarchy; a sheet
// of all 7s scores 7 (weights sum to 1), and the weights come back.
TEST(ScoreBook, VesselSessionsUseAhpWeightsOnNineIndicators) {
  ScoreBook book;
  EXPECT_THROW(book.Submit("v", "vessel", "d", kSheet), ServiceError);  // 7 is not 9
  book.Submit("v", "vessel", "d", {7, 7, 7, 7, 7, 7, 7, 7, 7});
  const ScoreReport r = book.Report("v");
  EXPECT_EQ(r.sessions[0].scheme, "vessel_ahp");
  ASSERT_EQ(r.combined_weights.size(), 9u);
  double sum = 0.0;
  for (const double w : r.combined_weights) sum += w;
  EXPECT_NEAR(sum, 1.0, 1e-12);
  EXPECT_NEAR(r.sessions[0].comprehensive_score, 7.0, 1e-12);
}

// A pushed scenario makes a new trial: sheets of the old scene are dropped.
TEST(ScoreBook, ANewSceneStartsNewSheets) {
  ScoreBook book;
  book.Submit("s", "acupuncture", "d1", kSheet);
  book.Submit("s", "acupuncture", "d2", kSheet);
  book.Submit("s", "cutting", "d1", {9, 9, 9, 9, 9, 9, 9});
  const ScoreReport r = book.Report("s");
  EXPECT_EQ(r.sessions[0].experts, 1u);
  EXPECT_NEAR(r.sessions[0].comprehensive_score, 9.0, 1e-12);
}

}  // namespace
}  // namespace hapsim::service
