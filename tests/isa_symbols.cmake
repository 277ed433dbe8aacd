# cmake -P script: every function that one instruction set's SIMD objects export (nm types T, W
# and i) must belong to that set, by its namespace mosaic::simd::<isa> or its xsimd architecture.
# libmosaic is a static archive: an exported inline function compiled with AVX-512 flags can be
# the copy the linker keeps for baseline code, which then faults on older CPUs. Data (constant
# tables) is the same whatever the flags, so it is not checked.
#
# -DNM=<nm> -DISA=<sse41|avx2|avx512> -DOBJECTS=<object files joined by |>
foreach(var NM ISA OBJECTS)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "isa_symbols.cmake: -D${var}= is required")
  endif()
endforeach()

set(arch_sse41 "xsimd::sse4_1")
set(arch_avx2 "xsimd::avx2")
set(arch_avx512 "xsimd::avx512")
if(NOT DEFINED arch_${ISA})
  message(FATAL_ERROR "isa_symbols.cmake: unknown instruction set '${ISA}'")
endif()
set(owned "(mosaic::simd::${ISA}::|${arch_${ISA}})")

string(REPLACE "|" ";" objects "${OBJECTS}")
set(foreign "")
set(checked 0)
foreach(object IN LISTS objects)
  execute_process(COMMAND ${NM} -C --defined-only ${object} OUTPUT_VARIABLE listing
                  RESULT_VARIABLE status ERROR_VARIABLE errors)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "${NM} ${object} failed: ${errors}")
  endif()
  string(REPLACE ";" "\\;" listing "${listing}")
  string(REPLACE "\n" ";" lines "${listing}")
  foreach(line IN LISTS lines)
    if(NOT line MATCHES "^[0-9a-fA-F]* [TWi] (.*)$")
      continue()
    endif()
    set(symbol "${CMAKE_MATCH_1}")
    math(EXPR checked "${checked} + 1")
    if(NOT symbol MATCHES "${owned}")
      string(APPEND foreign "  ${object}: ${symbol}\n")
    endif()
  endforeach()
endforeach()

if(checked EQUAL 0)
  message(FATAL_ERROR "isa_symbols.cmake: no exported functions in ${OBJECTS}")
endif()
if(NOT foreign STREQUAL "")
  message(FATAL_ERROR "${ISA} objects export symbols that are not ${ISA}'s own:\n${foreign}")
endif()
message(STATUS "${ISA}: ${checked} exported functions, all in ${owned}")
