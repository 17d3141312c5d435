# ESDSLAM_SANITIZE="address,undefined" or "thread" instruments every target of the build.
if(ESDSLAM_SANITIZE)
  add_compile_options(-fsanitize=${ESDSLAM_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=${ESDSLAM_SANITIZE})
endif()
