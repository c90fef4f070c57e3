// Argument checks shared by the partitioners (internal to the domain module).
#pragma once

#include <cmath>
#include <span>

#include "polydem/core/strings.h"
#include "polydem/domain/block_forest.h"
#include "polydem/domain/domain_error.h"

namespace polydem::domain::detail {

inline void checkWeights(const BlockForest& forest, std::span<const double> weights,
                         const char* who) {
  if (static_cast<int>(weights.size()) != forest.numBlocks()) {
    throw DomainError(
        cat(who, ": ", weights.size(), " weights for ", forest.numBlocks(), " blocks"));
  }
  for (std::size_t b = 0; b < weights.size(); ++b) {
    if (!(weights[b] >= 0) || !std::isfinite(weights[b])) {
      throw DomainError(
          cat(who, ": block ", b, " has weight ", weights[b], "; weights must be finite and >= 0"));
    }
  }
}

inline void checkRanks(const BlockForest& forest, int ranks, const char* who) {
  if (ranks < 1) throw DomainError(cat(who, ": ", ranks, " ranks"));
  if (ranks > forest.numBlocks()) {
    throw DomainError(cat(who, ": ", ranks, " ranks but only ", forest.numBlocks(), " blocks (",
                          forest.counts()[0], " x ", forest.counts()[1], " x ", forest.counts()[2],
                          "); every rank needs a block: use more blocks (chooseBlockCounts) or "
                          "fewer ranks"));
  }
}

inline void checkMap(const BlockForest& forest, std::span<const int> map, int ranks,
                     const char* who) {
  if (static_cast<int>(map.size()) != forest.numBlocks()) {
    throw DomainError(
        cat(who, ": map has ", map.size(), " entries for ", forest.numBlocks(), " blocks"));
  }
  for (std::size_t b = 0; b < map.size(); ++b) {
    if (map[b] < 0 || map[b] >= ranks) {
      throw DomainError(cat(who, ": block ", b, " on rank ", map[b], ", outside [0, ", ranks, ")"));
    }
  }
}

}  // namespace polydem::domain::detail
