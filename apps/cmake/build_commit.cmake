# Writes OUTPUT (a header) with the commit of SOURCE_DIR and whether its tracked files had
# uncommitted changes, at build time; the file is rewritten only when that changes, so that an
# unchanged tree does not rebuild anything. Run by the terratraj_build_commit target.
execute_process(COMMAND git -C "${SOURCE_DIR}" rev-parse HEAD
  OUTPUT_VARIABLE commit OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE failed)
if(failed)
  set(commit "")
endif()
execute_process(COMMAND git -C "${SOURCE_DIR}" status --porcelain --untracked-files=no
  OUTPUT_VARIABLE changes OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(changes STREQUAL "")
  set(dirty false)
else()
  set(dirty true)
endif()
set(text "#pragma once
// Generated at build time by apps/cmake/build_commit.cmake: the source tree this binary was
// built from.
namespace terratraj::apps::detail {
inline constexpr const char* kBuildCommit = \"${commit}\";
inline constexpr bool kBuildHadUncommittedChanges = ${dirty};
}  // namespace terratraj::apps::detail
")
if(EXISTS "${OUTPUT}")
  file(READ "${OUTPUT}" old)
else()
  set(old "")
endif()
if(NOT old STREQUAL text)
  file(WRITE "${OUTPUT}" "${text}")
endif()
