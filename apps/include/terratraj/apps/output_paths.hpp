#pragma once
// Output paths checked before any computation (the contract's "Verdicts": a long run must not
// find an unwritable output only at its end and lose its results).

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace terratraj::apps {

/// Creates the folder of `file` and checks that `file` can be written (an existing file is
/// opened for appending and left as it was; a new one is created and removed). Throws
/// InputError naming `option` and the path otherwise.
void ensureWritableFile(const std::filesystem::path& file, const std::string& option);

/// Creates `folder` and checks that files can be written in it (a probe file is created and
/// removed). Throws InputError naming `option` and the path otherwise.
void ensureWritableFolder(const std::filesystem::path& folder, const std::string& option);

/// Checks that `folder` exists and can be read. Throws InputError naming `option` otherwise.
void ensureReadableFolder(const std::filesystem::path& folder, const std::string& option);

/// The CLI's cache directory (the motion primitives): $TERRATRAJ_CACHE_DIR, else
/// $XDG_CACHE_HOME/terratraj, else $HOME/.cache/terratraj; empty when none of them is set (no
/// cache: primitives are generated every time, and the log says so).
std::filesystem::path primitiveCacheDirectory();

/// Writes `json` to `file` (its folder created) with `indent`. Throws InputError naming the file
/// when it cannot be written.
void writeJsonFile(const nlohmann::json& json, const std::filesystem::path& file, int indent = 2);

}  // namespace terratraj::apps
