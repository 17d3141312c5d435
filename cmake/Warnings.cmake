# Warnings are on for every target of ours and kept clean.
function(esdslam_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic)
  if(ESDSLAM_PCH)
    target_compile_options(${target} PRIVATE -Winvalid-pch)  # a precompiled set GCC had to ignore
  endif()
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${target} PRIVATE -Wshadow=local)  # clang (the fuzz build) has no =local
  endif()
  if(ESDSLAM_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
