# Writes version.cpp with the build's name (run at every build by the target aggpack_version,
# so that a new commit renames the build without a new configure; configure_file leaves the
# file untouched, and nothing recompiles, when the name is the same).
#   cmake -DSOURCE_DIR=... -DPROJECT_VERSION=... -DINPUT=src/core/version.cpp.in -DOUTPUT=version.cpp -P aggpack_version.cmake
# The name: PROJECT_VERSION+git.<commit>[.dirty] from `git describe` in a clone; in a source
# tarball made by `git archive` (GitHub's too), the commit that export-subst wrote into
# cmake/git_archival.txt; else PROJECT_VERSION+unknown (a build nothing can tell apart).
set(build_name "")
find_package(Git QUIET)
if(GIT_FOUND AND EXISTS "${SOURCE_DIR}/.git")
  execute_process(COMMAND "${GIT_EXECUTABLE}" describe --always --dirty=.dirty --abbrev=12 --match "NO-TAGS-USED"
                  WORKING_DIRECTORY "${SOURCE_DIR}" OUTPUT_VARIABLE described RESULT_VARIABLE failed
                  OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(NOT failed AND described)
    set(build_name "git.${described}")
  endif()
endif()
if(NOT build_name AND EXISTS "${SOURCE_DIR}/cmake/git_archival.txt")
  file(STRINGS "${SOURCE_DIR}/cmake/git_archival.txt" archived REGEX "^commit: [0-9a-f]+$")
  if(archived)
    string(REGEX REPLACE "^commit: ([0-9a-f]+)$" "\\1" commit "${archived}")
    string(SUBSTRING "${commit}" 0 12 commit)
    set(build_name "git.${commit}")
  endif()
endif()
if(NOT build_name)
  set(build_name "unknown")
endif()
set(AGGPACK_BUILD_VERSION "${PROJECT_VERSION}+${build_name}")
configure_file("${INPUT}" "${OUTPUT}" @ONLY)
