// The coloured noise of the generated recordings (pdpm-explain-data, the benchmark's surrogate and DEM
// cases): an AR(1) process with marginal standard deviation sigma and lag-one correlation rho,
//   x_i = rho x_{i-1} + sqrt(1 - rho^2) sigma e_i,   e_i ~ N(0, 1),
// started either from its stationary distribution (x_0 = sigma e_0) or from zero (a record whose
// noise builds up from the first sample). One definition, so that every generator draws the same
// sequence from the same seed. The caller's normal distribution is passed in: it caches every second
// draw, so generators that share one keep sharing it.
#pragma once
#include <cmath>
#include <random>

namespace pdpm::explain {

struct Ar1Noise {
    double rho = 0, sigma = 0;
    double x = 0;  ///< the current value

    /// The process started from its stationary distribution (one draw).
    template <class Rng>
    static Ar1Noise stationary(double rho, double sigma, Rng& rng, std::normal_distribution<double>& normal) {
        return {rho, sigma, normal(rng) * sigma};
    }
    /// The process started from zero.
    static Ar1Noise fromZero(double rho, double sigma) { return {rho, sigma, 0.0}; }

    /// Advance one sample; returns the new value.
    template <class Rng>
    double next(Rng& rng, std::normal_distribution<double>& normal) {
        x = rho * x + std::sqrt(1 - rho * rho) * sigma * normal(rng);
        return x;
    }
};

} // namespace pdpm::explain
