// What a path names when it is not a regular file, for messages: a FIFO or a directory given where
// a scene or a checkpoint is expected must be reported as such (a FIFO would block the reader
// forever, a directory is not "missing").
#pragma once

#include <string>

namespace polydem {

/// Empty if `path` names a regular file (after symbolic links); otherwise "no such file", "is a
/// directory", "is a FIFO (named pipe), not a file", "is a socket, not a file", "is a device, not
/// a file", or "cannot be inspected: <reason>".
std::string notARegularFile(const std::string& path);

}  // namespace polydem
