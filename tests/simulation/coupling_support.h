// What the proxy coupling's tests share: the device's force limit and a check of every force.
#pragma once

#include <cmath>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "osteon/simulation/coupling.h"

namespace osteon::test {

constexpr double kMaxN = 3.3;

// Every force sent to the device is finite and within N_max.
inline void expectSane(const simulation::HapticStep& h) {
  ASSERT_TRUE(std::isfinite(h.forceN.x) && std::isfinite(h.forceN.y) && std::isfinite(h.forceN.z));
  ASSERT_LE(glm::length(h.forceN), kMaxN + 1e-9);
}

}  // namespace osteon::test
