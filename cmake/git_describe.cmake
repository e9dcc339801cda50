# Run at every build (target wetdem_git_describe): writes OUT with the current `git describe` and the run
# version, touching it only when the text changes, so outputs name the commit actually built (not the one
# CMake last configured) and an unchanged tree recompiles nothing.
#
# The run version is a content hash of the sources that decide what a run computes: the shaders, the GPU system,
# the core, the run driver and its observables, and the public headers (shaders/, host/vk, host/gpu, host/core,
# host/app, include/), read as the compiler reads them: DIGEST (cmake/run_digest.cpp) writes their tokens, without
# comments, the layout of whitespace or the split of a string literal into pieces, to generated/run_sources.txt,
# and that text is hashed. A comment edit or a clang-format reflow keeps the stored runs (14 of the 120 commits
# before 7 Dec 2026 that touched these folders were such; docs/studies.md, "The run store"). A run's identity in a
# study store (study_file.h, run_hash) uses it instead of `git describe`, so a change to the study, diagnosis,
# command-line or script code, or a commit that touches none of these files, does not invalidate every stored run;
# a change to any of them does. The resource estimate (host/app/run/resources.*: what `wetdem check` quotes and
# the refusal of a run too large for the device) is left out: it decides whether a run starts, never what it
# computes, and a reworded estimate once invalidated a night of stored flowing-matrix runs. So are the stop
# signals (host/app/run/stop_signals.*): they decide where a run stops, and a resumed run ends bitwise where an
# uninterrupted one ends.
execute_process(COMMAND git describe --always --dirty --tags WORKING_DIRECTORY ${SRC}
                OUTPUT_VARIABLE git OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT git)
  set(git "unknown")
endif()
set(files)
foreach(dir shaders host/vk host/gpu host/core host/app include)
  file(GLOB_RECURSE found LIST_DIRECTORIES false RELATIVE ${SRC} ${SRC}/${dir}/*)
  list(APPEND files ${found})
endforeach()
list(FILTER files EXCLUDE REGEX "^host/app/run/(resources|stop_signals)\\.(h|cpp)$")
list(SORT files)
get_filename_component(dir ${OUT} DIRECTORY)
execute_process(COMMAND ${DIGEST} ${SRC} ${dir}/run_sources.txt ${files} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "wetdem_run_digest failed (${rc}): the run version cannot be computed")
endif()
file(SHA1 ${dir}/run_sources.txt run)
string(SUBSTRING "${run}" 0 12 run)
set(text "#define WETDEM_GIT \"${git}\"\n#define WETDEM_RUN_SOURCES \"${run}\"\n")
if(EXISTS ${OUT})
  file(READ ${OUT} old)
endif()
if(NOT "${old}" STREQUAL "${text}")
  file(WRITE ${OUT} "${text}")
endif()
