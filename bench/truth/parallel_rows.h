#pragma once
// Rows of an image shared among the machine's cores, row y to thread y mod N: the truths and the lookup
// replay are per pixel and independent. `body(y)` must touch only row y's outputs.

#include <algorithm>
#include <thread>
#include <vector>

namespace omnishadow::bench {

template <typename Body>
void parallel_rows(int height, Body body) {
  unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      for (int y = static_cast<int>(t); y < height; y += static_cast<int>(threads)) body(y);
    });
  for (auto& th : pool) th.join();
}

}  // namespace omnishadow::bench
