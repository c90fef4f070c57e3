// The error thrown by the domain module: a block layout or a partitioning request that cannot be
// satisfied (more ranks than blocks, a weight vector of the wrong length, a negative weight).
#pragma once

#include "polydem/core/error.h"

namespace polydem::domain {

class DomainError : public Error {
 public:
  using Error::Error;
};

}  // namespace polydem::domain
