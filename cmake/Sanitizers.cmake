# ESDSLAM_SANITIZE="address,undefined" or "thread" instruments every target of the build.
if(ESDSLAM_SANITIZE)
  add_compile_options(-fsanitize=${ESDSLAM_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=${ESDSLAM_SANITIZE})
  # GCC 12 reports libstdc++'s own <regex> internals (std::function in _State) as "may be used
  # uninitialized" under the sanitizers' instrumentation (14 per file using std::regex; the
  # Release build, which keeps the warning, has none).
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    add_compile_options(-Wno-maybe-uninitialized)
  endif()
endif()
