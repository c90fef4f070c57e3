// Test hook: a pause at a named point of a run, so that a test can send a signal or kill -9 the
// process exactly there (tests/apps/signal_cli_test.sh, checkpoint_cli_test.sh).
//
//   POLYDEM_TEST_PAUSE="where:seconds[,where:seconds...]"
//
// Points: "startup" (signal handlers installed, no file read yet), "checkpoint-write" (a
// checkpoint's temporary file created, its data not yet written), "before-rename" (the
// temporary file complete, not yet renamed), "after-run" (the last step done, the final outputs
// not yet written), "fos-trial" (a trial of `polydem fos` set up, its first step not yet
// taken). At a point named in the variable, the process prints
// "polydem test pause: <where>, <seconds> s (pid <pid>)" on stderr and sleeps that long; a
// signal does not cut the pause short. Unset (the normal case): nothing happens.
#pragma once

#include <string_view>

namespace polydem {

/// Pauses here if POLYDEM_TEST_PAUSE names `where` (see above).
void testPause(std::string_view where);

}  // namespace polydem
