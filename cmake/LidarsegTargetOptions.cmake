# Per-target compile settings shared by every lidarseg target.
#   lidarseg_target_options(<target>) : C++17, warnings, optional sanitizers.

set(LIDARSEG_SANITIZER_FLAGS "")
if(LIDARSEG_SANITIZE)
  set(LIDARSEG_SANITIZER_FLAGS -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
endif()

function(lidarseg_target_options target)
  target_compile_features(${target} PUBLIC cxx_std_17)
  set_target_properties(${target} PROPERTIES CXX_EXTENSIONS OFF POSITION_INDEPENDENT_CODE ON)
  if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion)
  endif()
  if(LIDARSEG_SANITIZE)
    target_compile_options(${target} PRIVATE ${LIDARSEG_SANITIZER_FLAGS})
    target_link_options(${target} PRIVATE ${LIDARSEG_SANITIZER_FLAGS})
  endif()
endfunction()

# Third-party headers (MRPT, Eigen) trigger -Wconversion/-Wshadow noise: adapters
# include them as SYSTEM through imported targets, which CMake already does.
