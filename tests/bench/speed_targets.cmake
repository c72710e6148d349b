# Issue 22's speed targets, checked against laptrainer-bench's JSON output:
#
#   cmake -DJSON=FILE -P tests/bench/speed_targets.cmake
#
# FILE is `laptrainer-bench --benchmark_filter='FullAnatomy/hard|ScenarioLoadToFirstTick/warm'
# --benchmark_format=json` (packaging/check-speed.sh runs it). With --benchmark_repetitions the
# median of the repetitions is judged, else the one run. Prints each figure against its target;
# fails naming every figure over its target and every benchmark missing from the file.
# The targets are issue 22's ("Speed with the whole anatomy"), for the hardest patient:
#   BM_HapticTickFullAnatomy   one haptic tick against every organ: median <= 20 us, p99.9 <= 100 us
#   BM_ModelStepFullAnatomy    one modelling step: median <= 1 ms
#   BM_ScenarioLoadToFirstTick scenario load to the first haptic tick, modal cache warm: <= 2 s
# Not run by CI: these figures are the machine's (docs/benchmarks.md), and a shared machine's
# noise would make a timed check fail at random.
cmake_minimum_required(VERSION 3.19)  # string(JSON)
if(NOT DEFINED JSON)
  message(FATAL_ERROR "speed_targets.cmake: give the benchmark's JSON output: -DJSON=FILE")
endif()
if(NOT EXISTS "${JSON}")
  message(FATAL_ERROR "speed_targets.cmake: ${JSON}: no such file (expected laptrainer-bench's "
                      "--benchmark_format=json output)")
endif()
file(READ "${JSON}" text)
string(JSON count ERROR_VARIABLE bad LENGTH "${text}" benchmarks)
if(bad)
  message(FATAL_ERROR "speed_targets.cmake: ${JSON}: not Google Benchmark's JSON output (${bad})")
endif()
if(count EQUAL 0)
  message(FATAL_ERROR "speed_targets.cmake: ${JSON}: no benchmarks in it (expected those of "
                      "--benchmark_filter='FullAnatomy/hard|ScenarioLoadToFirstTick/warm')")
endif()

# Each target: benchmark (its run_name up to the first '/' after the argument), counter, the
# most it may be in the counter's own unit, and that limit as the issue states it.
set(targets
  "BM_HapticTickFullAnatomy/hard|median_ns|20000|20 us"
  "BM_HapticTickFullAnatomy/hard|p999_ns|100000|100 us"
  "BM_ModelStepFullAnatomy/hard|median_ns|1000000|1 ms"
  "BM_ScenarioLoadToFirstTick/warm|real_time|2|2 s")  # the mean of its three loads, in s

set(misses "")
foreach(target IN LISTS targets)
  string(REPLACE "|" ";" t "${target}")
  list(GET t 0 bench)
  list(GET t 1 counter)
  list(GET t 2 limit)
  list(GET t 3 stated)
  # The repetitions' median if there is one, else the single run (the last one listed).
  set(value "")
  set(from "")
  math(EXPR last "${count} - 1")
  foreach(i RANGE 0 ${last})
    string(JSON run_name ERROR_VARIABLE e GET "${text}" benchmarks ${i} run_name)
    string(FIND "${run_name}/" "${bench}/" at)  # the name alone, or with /iterations:N...
    if(e OR NOT at EQUAL 0)
      continue()
    endif()
    string(JSON run_type ERROR_VARIABLE e GET "${text}" benchmarks ${i} run_type)
    string(JSON aggregate ERROR_VARIABLE e2 GET "${text}" benchmarks ${i} aggregate_name)
    string(JSON v ERROR_VARIABLE e3 GET "${text}" benchmarks ${i} ${counter})
    if(e3)
      continue()
    endif()
    if(counter STREQUAL "real_time")
      string(JSON time_unit ERROR_VARIABLE e4 GET "${text}" benchmarks ${i} time_unit)
      if(NOT time_unit STREQUAL "s")
        message(FATAL_ERROR "speed_targets.cmake: ${JSON}: ${bench}'s time is in '${time_unit}'; "
                            "expected 's' (the benchmark's Unit)")
      endif()
    endif()
    if(run_type STREQUAL "aggregate" AND aggregate STREQUAL "median")
      set(value "${v}")
      set(from "median of the repetitions")
      break()
    elseif(run_type STREQUAL "iteration")
      set(value "${v}")
      set(from "one run")
    endif()
  endforeach()
  if(value STREQUAL "")
    list(APPEND misses "${bench} ${counter}: not in the file (run the benchmark with --benchmark_filter='FullAnatomy/hard|ScenarioLoadToFirstTick/warm')")
    continue()
  endif()
  # CMake's if() compares the two as decimals.
  if(value GREATER limit)
    set(verdict "OVER")
    list(APPEND misses "${bench} ${counter} ${value} > ${limit} (${stated})")
  else()
    set(verdict "ok")
  endif()
  message(STATUS "${bench} ${counter} ${value} (${from}); target <= ${limit} (${stated}): "
                 "${verdict}")
endforeach()

if(misses)
  list(JOIN misses "\n  " listed)
  message(FATAL_ERROR "speed targets missed:\n  ${listed}")
endif()
message(STATUS "every speed target met")
