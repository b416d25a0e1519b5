#pragma once
// InputError: the one exception type for bad user input (files, keys, values).
//
// Thrown by loaders and validators outside any solver callback; the message names the file,
// key or value at fault, ready to print. The command-line front end maps it to exit status 2.

#include <stdexcept>
#include <string>

namespace terratraj {

/// Bad input from a user: a file that cannot be read, a key or value that is not allowed.
/// what() is a complete sentence naming the file / key / value at fault.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace terratraj
