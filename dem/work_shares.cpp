#include "dem/work_shares.h"

#include <algorithm>

namespace pilelab::dem {

void WorkShares::prepare(int threads) {
  const auto n = static_cast<std::size_t>(std::max(threads, 1));
  if (begin_.size() == n + 1) return;
  records_.assign(n, Record{});
  rate_.assign(n, 0.0);
  begin_.resize(n + 1);
  for (std::size_t t = 0; t <= n; ++t) begin_[t] = double(t) / double(n);
}

double WorkShares::begin(int thread, int threads) const {
  if (thread >= threads) return 1.0;
  if (begin_.size() != static_cast<std::size_t>(threads) + 1) return double(thread) / double(threads);
  return begin_[thread];
}

void WorkShares::record(int thread, int threads, double cost, double seconds) {
  if (records_.size() != static_cast<std::size_t>(threads) || thread >= threads) return;
  records_[thread].cost += cost;
  records_[thread].seconds += seconds;
}

void WorkShares::update() {
  const std::size_t n = rate_.size();
  if (n < 2) return;
  for (std::size_t t = 0; t < n; ++t) {
    const Record r = records_[t];
    records_[t] = Record{};
    if (!(r.cost > 0.0 && r.seconds > 0.0)) continue;
    const double rate = r.cost / r.seconds;
    // One slow step (the thread was held up) moves the smoothed rate by a bounded amount.
    rate_[t] = rate_[t] == 0.0 ? rate : rate_[t] + smoothing * (std::clamp(rate, 0.5 * rate_[t], 2.0 * rate_[t]) - rate_[t]);
  }
  if (std::find(rate_.begin(), rate_.end(), 0.0) != rate_.end()) return;  // not every thread measured yet
  // Shares in proportion to the rates make the parts take equal times (for a cost that grows
  // in proportion to the part; where it does not, the next steps' rates correct the shares).
  double total = 0.0;
  for (double r : rate_) total += r;
  for (std::size_t t = 0; t < n; ++t)
    begin_[t + 1] = begin_[t] + std::clamp(rate_[t] / total, least_share / double(n), (2.0 - least_share) / double(n));
  for (std::size_t t = 1; t < n; ++t) begin_[t] /= begin_[n];
  begin_[n] = 1.0;
}

}  // namespace pilelab::dem
