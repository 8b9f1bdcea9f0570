// Sums over particles whose result does not depend on the number of OpenMP threads: fixed-size
// chunks are summed in parallel, then the chunk sums are added in order.
#pragma once
#include <algorithm>
#include <cstddef>
#include <vector>

namespace pdpm {

template <class F>
double deterministicSum(std::size_t n, F&& term) {
    constexpr std::size_t kChunk = 4096;
    const std::size_t nChunks = (n + kChunk - 1) / kChunk;
    std::vector<double> partial(nChunks, 0.0);
#pragma omp parallel for schedule(static)
    for (long c = 0; c < static_cast<long>(nChunks); ++c) {
        double s = 0;
        const std::size_t b = static_cast<std::size_t>(c) * kChunk, e = std::min(n, b + kChunk);
        for (std::size_t i = b; i < e; ++i) s += term(i);
        partial[c] = s;
    }
    double s = 0;
    for (double p : partial) s += p;
    return s;
}

} // namespace pdpm
