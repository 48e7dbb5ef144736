// Patch budget: the rate (burst, then the sustained rate), the per-vehicle and total quotas, and
// a vehicle's flood leaving another vehicle's budget alone.
#include "map_server/patch_budget.h"

#include <gtest/gtest.h>

namespace fleetloc::map_server {
namespace {

TEST(PatchBudget, ABurstThenTheSustainedRate) {
  PatchBudget budget({2.0, 5, 1000, 1LL << 40, 1LL << 40, 16});
  for (int i = 0; i < 5; ++i)
    EXPECT_EQ(budget.Admit("agv-1", 100, 10.0), BudgetVerdict::kAccept) << i;
  EXPECT_EQ(budget.Admit("agv-1", 100, 10.0), BudgetVerdict::kRateLimited);
  EXPECT_EQ(budget.Admit("agv-2", 100, 10.0), BudgetVerdict::kAccept);       // its own bucket
  EXPECT_EQ(budget.Admit("agv-1", 100, 10.4), BudgetVerdict::kRateLimited);  // 0.8 tokens
  EXPECT_EQ(budget.Admit("agv-1", 100, 10.5), BudgetVerdict::kAccept);       // 1 token
  // 100 s of flooding at 100 patches/s yields about 2 per second.
  int accepted = 0;
  for (int i = 0; i < 10000; ++i)
    accepted += budget.Admit("agv-1", 100, 11.0 + i * 0.01) == BudgetVerdict::kAccept;
  EXPECT_NEAR(accepted, 200, 2);
  EXPECT_EQ(budget.Usage("agv-1").patches, 6 + accepted);
}

TEST(PatchBudget, QuotasStopAVehicleAndEveryone) {
  PatchBudget budget({1000.0, 1000, 3, 250, 600, 16});
  EXPECT_EQ(budget.Admit("agv-1", 100, 0), BudgetVerdict::kAccept);
  EXPECT_EQ(budget.Admit("agv-1", 100, 0), BudgetVerdict::kAccept);
  EXPECT_EQ(budget.Admit("agv-1", 100, 0), BudgetVerdict::kOverVehicleQuota);  // 300 bytes > 250
  budget.Unreserve("agv-1", 100);
  EXPECT_EQ(budget.Admit("agv-1", 100, 0), BudgetVerdict::kAccept);
  EXPECT_EQ(budget.Admit("agv-2", 200, 0), BudgetVerdict::kAccept);
  EXPECT_EQ(budget.Admit("agv-3", 200, 0), BudgetVerdict::kAccept);
  EXPECT_EQ(budget.Admit("agv-4", 200, 0), BudgetVerdict::kOverTotalQuota);  // 800 > 600
  for (const auto& [vehicle, bytes] :
       {std::pair{"agv-1", 100}, {"agv-1", 100}, {"agv-2", 200}, {"agv-3", 200}}) {
    budget.Commit(vehicle, bytes);  // all stored
  }
  budget.SetUsage({{"agv-1", {3, 10}}});  // what the store says after a prune
  EXPECT_EQ(budget.Admit("agv-1", 10, 0), BudgetVerdict::kOverVehicleQuota);  // 4 patches > 3
  EXPECT_EQ(budget.Admit("agv-4", 200, 0), BudgetVerdict::kAccept);
  EXPECT_STREQ(BudgetVerdictName(BudgetVerdict::kRateLimited), "patches_rate_limited");
}

// A prune refreshes the usage from the store while patches are still queued for it: those
// reservations must survive, or a flooding vehicle gets past its quota (seen under load: 8
// patches stored of a quota of 7).
TEST(PatchBudget, ReservationsInFlightSurviveARefreshFromTheStore) {
  PatchBudget budget({1000.0, 1000, 1000, 300, 1LL << 40, 16});
  EXPECT_EQ(budget.Admit("agv-1", 100, 0), BudgetVerdict::kAccept);
  budget.Commit("agv-1", 100);                                       // stored
  EXPECT_EQ(budget.Admit("agv-1", 100, 0), BudgetVerdict::kAccept);  // queued
  EXPECT_EQ(budget.Admit("agv-1", 100, 0), BudgetVerdict::kAccept);  // queued
  budget.SetUsage({{"agv-1", {1, 100}}});  // the store holds the first only
  EXPECT_EQ(budget.Usage("agv-1").bytes, 300);
  EXPECT_EQ(budget.Admit("agv-1", 100, 0), BudgetVerdict::kOverVehicleQuota);
  budget.Unreserve("agv-1", 100);  // one queued patch was not stored after all
  budget.Commit("agv-1", 100);     // the other was
  EXPECT_EQ(budget.Usage("agv-1").bytes, 200);
  EXPECT_EQ(budget.Admit("agv-1", 100, 0), BudgetVerdict::kAccept);
}

}  // namespace
}  // namespace fleetloc::map_server
