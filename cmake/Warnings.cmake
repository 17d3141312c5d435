# Warnings are on for every target of ours and kept clean.
function(esdslam_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow=local)
  if(ESDSLAM_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
