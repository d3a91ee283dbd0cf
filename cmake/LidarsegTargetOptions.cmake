# Per-target compile settings shared by every lidarseg target.
#   lidarseg_target_options(<target>) : C++17, warnings, optional sanitizers.

# Sanitizer builds (docs/reliability.md): at most one of
#   LIDARSEG_SANITIZE  AddressSanitizer + UndefinedBehaviorSanitizer (the test suite, ./run.sh test)
#   LIDARSEG_TSAN      ThreadSanitizer (./run.sh tsan)
#   LIDARSEG_FUZZ      libFuzzer targets, clang only, with ASan + UBSan (./run.sh fuzz)
set(LIDARSEG_SANITIZER_FLAGS "")
if((LIDARSEG_SANITIZE AND LIDARSEG_TSAN) OR (LIDARSEG_FUZZ AND LIDARSEG_TSAN))
  message(FATAL_ERROR "LIDARSEG_TSAN cannot be combined with LIDARSEG_SANITIZE or LIDARSEG_FUZZ")
endif()
if(LIDARSEG_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "LIDARSEG_FUZZ needs clang (libFuzzer): configure with -DCMAKE_CXX_COMPILER=clang++")
  endif()
  set(LIDARSEG_SANITIZER_FLAGS -fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer
      -fno-sanitize-recover=undefined)
elseif(LIDARSEG_SANITIZE)
  set(LIDARSEG_SANITIZER_FLAGS -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
elseif(LIDARSEG_TSAN)
  set(LIDARSEG_SANITIZER_FLAGS -fsanitize=thread -fno-omit-frame-pointer)
endif()

function(lidarseg_target_options target)
  target_compile_features(${target} PUBLIC cxx_std_17)
  set_target_properties(${target} PROPERTIES CXX_EXTENSIONS OFF POSITION_INDEPENDENT_CODE ON)
  if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion)
  endif()
  if(LIDARSEG_SANITIZER_FLAGS)
    target_compile_options(${target} PRIVATE ${LIDARSEG_SANITIZER_FLAGS})
    target_link_options(${target} PRIVATE ${LIDARSEG_SANITIZER_FLAGS})
  endif()
endfunction()

# Third-party headers (MRPT, Eigen) trigger -Wconversion/-Wshadow noise: adapters
# include them as SYSTEM through imported targets, which CMake already does.

# lidarseg_add_library(<short name> SOURCES ... [DEPENDS ...] [NO_INSTALL])
# Defines target lidarseg_<name> with alias lidarseg::<name>, public headers under
# include/, the project's compile options and, unless NO_INSTALL, its installation into
# the exported lidarseg package.
function(lidarseg_add_library name)
  cmake_parse_arguments(ARG "NO_INSTALL" "" "SOURCES;DEPENDS" ${ARGN})
  set(target lidarseg_${name})
  if(ARG_NO_INSTALL)
    # Internal to the tools: linked into them, never shipped, whatever BUILD_SHARED_LIBS says.
    add_library(${target} STATIC ${ARG_SOURCES})
  else()
    add_library(${target} ${ARG_SOURCES})
  endif()
  add_library(lidarseg::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME ${target}
    VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${target} PUBLIC ${ARG_DEPENDS})
  lidarseg_target_options(${target})
  if(NOT ARG_NO_INSTALL)
    install(TARGETS ${target} EXPORT lidarsegTargets
      ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
      LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
      RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
    install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  endif()
endfunction()
