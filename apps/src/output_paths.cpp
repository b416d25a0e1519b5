#include "terratraj/apps/output_paths.hpp"

#include <cstdlib>

#include <unistd.h>

#include <fstream>
#include <system_error>

#include "terratraj/terrain/input_error.hpp"

namespace terratraj::apps {
namespace {

void createFolder(const std::filesystem::path& folder, const std::string& option) {
  if (folder.empty()) return;
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) {
    throw InputError(option + ": cannot create the folder '" + folder.string() +
                     "': " + error.message());
  }
  if (!std::filesystem::is_directory(folder, error)) {
    throw InputError(option + ": '" + folder.string() + "' is not a folder");
  }
}

}  // namespace

void ensureWritableFile(const std::filesystem::path& file, const std::string& option) {
  if (file.empty()) throw InputError(option + ": the path is empty");
  createFolder(file.parent_path(), option);
  std::error_code error;
  if (std::filesystem::is_directory(file, error)) {
    throw InputError(option + ": '" + file.string() + "' is a folder, not a file");
  }
  const bool existed = std::filesystem::exists(file, error);
  {
    std::ofstream probe(file, std::ios::app);
    if (!probe) throw InputError(option + ": '" + file.string() + "' cannot be written");
  }
  if (!existed) std::filesystem::remove(file, error);
}

void ensureWritableFolder(const std::filesystem::path& folder, const std::string& option) {
  createFolder(folder, option);
  const std::filesystem::path probe =
      (folder.empty() ? std::filesystem::path(".") : folder) /
      (".terratraj-write-probe-" + std::to_string(static_cast<long>(::getpid())));
  {
    std::ofstream out(probe);
    if (!out) {
      throw InputError(option + ": cannot write in the folder '" + folder.string() + "'");
    }
  }
  std::error_code error;
  std::filesystem::remove(probe, error);
}

void ensureReadableFolder(const std::filesystem::path& folder, const std::string& option) {
  std::error_code error;
  if (!std::filesystem::is_directory(folder, error)) {
    throw InputError(option + ": '" + folder.string() + "' is not an existing folder");
  }
  std::filesystem::directory_iterator it(folder, error);
  if (error) {
    throw InputError(option + ": '" + folder.string() + "' cannot be read: " + error.message());
  }
}

void writeJsonFile(const nlohmann::json& json, const std::filesystem::path& file, int indent) {
  createFolder(file.parent_path(), file.string());
  std::ofstream out(file);
  out << json.dump(indent) << '\n';
  out.flush();
  if (!out) throw InputError(file.string() + ": cannot be written");
}

std::filesystem::path primitiveCacheDirectory() {
  if (const char* dir = std::getenv("TERRATRAJ_CACHE_DIR"); dir && *dir) return dir;
  if (const char* dir = std::getenv("XDG_CACHE_HOME"); dir && *dir) {
    return std::filesystem::path(dir) / "terratraj";
  }
  if (const char* home = std::getenv("HOME"); home && *home) {
    return std::filesystem::path(home) / ".cache" / "terratraj";
  }
  return {};
}

}  // namespace terratraj::apps
