// Counts calls of the global operator new, so that a test can check that a warm hot path
// allocates nothing. Linking polydem_test_allocation_counter into a test binary replaces the
// global allocation functions of that binary only.
#pragma once

namespace polydem::testing {

/// operator new calls in this process so far.
long allocationCount();
/// Bytes asked of operator new in this process so far (never decreases on delete).
long long allocatedBytes();

}  // namespace polydem::testing
