// ScoreBook: what clients can make the server keep is bounded (issue 15,
// reliability.md gap 8), and refusing more loses nothing already kept.
#include "hapsim/service/score_book.h"

#include <gtest/gtest.h>

#include "hapsim/service/errors.h"

namespace hapsim::service {
namespace {

const std::vector<double> kSheet = {5, 5, 5, 5, 5, 5, 5};

ErrorCode SubmitError(ScoreBook& book, const std::string& session, const std::string& expert) {
  try {
    book.Submit(session, expert, kSheet);
  } catch (const ServiceError& e) {
    return e.code();
  }
  ADD_FAILURE() << "accepted " << session << "/" << expert;
  return ErrorCode::kInvalidArgument;
}

TEST(ScoreBook, ANewExpertBeyondTheLimitIsRefusedButEveryKeptExpertMayRescore) {
  ScoreBook book;
  for (std::size_t i = 0; i < ScoreBook::kMaxExpertsPerSession; ++i) {
    book.Submit("s", "expert" + std::to_string(i), kSheet);
  }
  EXPECT_EQ(SubmitError(book, "s", "one-too-many"), ErrorCode::kResourceExhausted);
  EXPECT_NO_THROW(book.Submit("s", "expert0", {9, 9, 9, 9, 9, 9, 9}));  // replacing is not growing
  hapsim::v1::ScoreReport report;
  book.Report("s", &report);
  ASSERT_EQ(report.sessions_size(), 1);
  EXPECT_EQ(report.sessions(0).experts(), ScoreBook::kMaxExpertsPerSession);
  // Mean of indicator 0 over 32 experts: one 9, thirty-one 5s.
  EXPECT_NEAR(report.sessions(0).mean_indicators(0), (9.0 + 31 * 5.0) / 32.0, 1e-12);
}

TEST(ScoreBook, ANewSessionBeyondTheLimitIsRefusedButKeptSessionsStillTakeSheets) {
  ScoreBook book;
  for (std::size_t i = 0; i < ScoreBook::kMaxScoredSessions; ++i) {
    std::string id = "s";  // (not "s" + to_string: GCC 12's -Wrestrict false positive)
    id += std::to_string(i);
    book.Submit(id, "e", kSheet);
  }
  EXPECT_EQ(SubmitError(book, "one-too-many", "e"), ErrorCode::kResourceExhausted);
  EXPECT_NO_THROW(book.Submit("s0", "another-expert", kSheet));
  hapsim::v1::ScoreReport report;
  book.Report("", &report);
  EXPECT_EQ(report.sessions_size(), static_cast<int>(ScoreBook::kMaxScoredSessions));
}

}  // namespace
}  // namespace hapsim::service
