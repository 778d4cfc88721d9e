# Sample scenes under samples/, made by exporters/blender/make_samples.py.
#
#   samples_wellformed  every committed .gltf parses, its buffers and images
#                       exist with the declared sizes, and it has at least one
#                       camera, light and mesh (tests/gltf_content.py --check).
#   samples_animated    the animated samples (PB_ANIMATED_SAMPLES below) each
#                       move the intended node (and only it) by node TRS keys,
#                       49 of them from 0 to 2 s, starting from the node's
#                       static pose (tests/gltf_content.py --animated).
#   samples_reexport    when Blender is installed: re-export every sample
#                       (every folder under samples/, animated ones included)
#                       into the build tree and compare each with the
#                       committed file by content, animations included
#                       (tests/gltf_content.py A B); skipped without Blender.
#
# This file is included by tests/CMakeLists.txt (PB_ROOT, Python3_EXECUTABLE)
# and is also the script samples_reexport runs (cmake -P, with BLENDER, PYTHON,
# ROOT and WORK defined), so the whole test lives in one place.

if(CMAKE_SCRIPT_MODE_FILE)
  # ---- script mode: the body of samples_reexport -------------------------
  file(REMOVE_RECURSE "${WORK}")
  file(MAKE_DIRECTORY "${WORK}")
  # Blender's embedded Python picks up the first python3 on PATH, and a pyenv
  # interpreter breaks its glTF exporter: run Blender without pyenv's
  # directories (as validation/cycles_calib_check.py does).
  string(REPLACE ":" ";" path_dirs "$ENV{PATH}")
  list(FILTER path_dirs EXCLUDE REGEX "[.]pyenv")
  string(REPLACE ";" ":" path_clean "${path_dirs}")
  set(ENV{PATH} "${path_clean}")
  execute_process(
    COMMAND "${BLENDER}" -b --factory-startup --python-exit-code 1
            -P "${ROOT}/exporters/blender/make_samples.py" -- --out "${WORK}"
    RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "Blender export failed (exit ${rc}):\n${log}")
  endif()
  string(REGEX MATCHALL "make_samples:[^\n]*" summary "${log}")
  foreach(line ${summary})
    message(STATUS "${line}")
  endforeach()

  file(GLOB committed RELATIVE "${ROOT}/samples" "${ROOT}/samples/*/*.gltf")
  file(GLOB produced RELATIVE "${WORK}" "${WORK}/*/*.gltf")
  list(SORT committed)
  list(SORT produced)
  if(NOT committed)
    message(FATAL_ERROR "no committed samples under ${ROOT}/samples")
  endif()
  set(failed "")
  if(NOT committed STREQUAL produced)
    list(APPEND failed "file lists differ: committed [${committed}], re-exported [${produced}]")
  endif()
  foreach(f ${committed})
    if(NOT EXISTS "${WORK}/${f}")
      continue()
    endif()
    execute_process(
      COMMAND "${PYTHON}" "${ROOT}/tests/gltf_content.py" "${ROOT}/samples/${f}" "${WORK}/${f}"
      RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
    message(STATUS "${out}")
    if(NOT rc EQUAL 0)
      list(APPEND failed "${f}")
    endif()
  endforeach()
  if(failed)
    message(FATAL_ERROR "re-exported samples differ from the committed ones: ${failed}\n"
            "If the change is intended, regenerate with\n"
            "  blender -b --factory-startup -P exporters/blender/make_samples.py -- --out samples")
  endif()
else()
  # ---- included from tests/CMakeLists.txt: define the tests --------------
  if(NOT Python3_EXECUTABLE)
    message(STATUS "samples: no Python 3 interpreter; samples tests not added")
  else()
    add_test(NAME samples_wellformed
             COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/gltf_content.py --check ${PB_ROOT}/samples
             WORKING_DIRECTORY ${PB_ROOT})

    # Animated samples: file, node that moves, its kind, node TRS paths keyed.
    set(PB_ANIMATED_SAMPLES
        samples/cornell_box_moving_light/cornell_box_moving_light.gltf CeilingLight light translation
        samples/cornell_caustics_moving_sphere/cornell_caustics_moving_sphere.gltf GlassSphere mesh translation
        samples/sun_atrium_flythrough/sun_atrium_flythrough.gltf Camera camera translation,rotation)
    add_test(NAME samples_animated
             COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/gltf_content.py --animated ${PB_ANIMATED_SAMPLES}
             WORKING_DIRECTORY ${PB_ROOT})

    find_program(PB_BLENDER blender)
    if(PB_BLENDER)
      add_test(NAME samples_reexport
               COMMAND ${CMAKE_COMMAND}
                       -DBLENDER=${PB_BLENDER} -DPYTHON=${Python3_EXECUTABLE}
                       -DROOT=${PB_ROOT} -DWORK=${CMAKE_CURRENT_BINARY_DIR}/samples_reexport
                       -P ${CMAKE_CURRENT_LIST_FILE})
      set_tests_properties(samples_reexport PROPERTIES TIMEOUT 900)
    else()
      add_test(NAME samples_reexport
               COMMAND ${Python3_EXECUTABLE} -c
                       "print('samples_reexport: blender not found; skipped'); raise SystemExit(77)")
      set_tests_properties(samples_reexport PROPERTIES SKIP_RETURN_CODE 77)
    endif()
    set_tests_properties(samples_reexport PROPERTIES LABELS "blender;no-sanitize")
  endif()
endif()
