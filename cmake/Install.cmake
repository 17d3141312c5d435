# The installable library (README, "Use it as a library"):
#   esdslam_shared  libesdslam.so, exported as esdslam::esdslam: the public API (include/esdslam)
#                   with every stage inside; only the API's symbols are exported
#   esdslam_static  libesdslam.a, exported as esdslam::esdslam_static: the same objects
# Both are made from the stage libraries' objects (compiled once, position independent), so
# the program and the tests keep linking the stage libraries as before. `cmake --install`
# also installs the program, the models, the vocabulary, the shipped settings and the viewer's
# page under share/esdslam (found at run time, common/data_files.h), the CMake package and a
# pkg-config file; CPack makes a .deb of it (cpack -G DEB in the build folder).

set(ESDSLAM_INSTALL_DATA_DIR ${CMAKE_INSTALL_DATADIR}/esdslam)
set(ESDSLAM_LIBRARY_STAGES common camera feature io eval optim robust map place semantic tracking dynamic mapping
    loop dense system report viewer api)
set(ESDSLAM_LIBRARY_OBJECTS)
foreach(stage ${ESDSLAM_LIBRARY_STAGES})
  list(APPEND ESDSLAM_LIBRARY_OBJECTS $<TARGET_OBJECTS:esdslam_${stage}>)
endforeach()
# The third-party libraries of those stages (esdslam_base's list, as exportable targets).
set(ESDSLAM_THIRD_PARTY Eigen3::Eigen ${OpenCV_LIBS} Ceres::ceres yaml-cpp spdlog::spdlog fmt::fmt Threads::Threads
    ${OCTOMAP_LIBRARIES} ${HTTPLIB_LINK_LIBRARIES} ${DEFLATE_LINK_LIBRARIES})

add_library(esdslam_shared SHARED ${ESDSLAM_LIBRARY_OBJECTS})
target_link_libraries(esdslam_shared PRIVATE ${ESDSLAM_THIRD_PARTY})
# Only the public API's symbols are exported (cmake/esdslam.map); the stages' stay inside.
target_link_options(esdslam_shared PRIVATE -Wl,--version-script=${CMAKE_SOURCE_DIR}/cmake/esdslam.map)
set_property(TARGET esdslam_shared APPEND PROPERTY LINK_DEPENDS ${CMAKE_SOURCE_DIR}/cmake/esdslam.map)
set_target_properties(esdslam_shared PROPERTIES OUTPUT_NAME esdslam EXPORT_NAME esdslam
                      VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})

add_library(esdslam_static STATIC ${ESDSLAM_LIBRARY_OBJECTS})
target_link_libraries(esdslam_static PRIVATE ${ESDSLAM_THIRD_PARTY})
set_target_properties(esdslam_static PROPERTIES OUTPUT_NAME esdslam EXPORT_NAME esdslam_static)

foreach(lib esdslam_shared esdslam_static)
  target_include_directories(${lib} INTERFACE $<BUILD_INTERFACE:${CMAKE_SOURCE_DIR}/include>
                                              $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${lib} INTERFACE opencv_core)  # cv::Mat in the public header
  target_compile_features(${lib} INTERFACE cxx_std_17)
endforeach()
add_library(esdslam::esdslam ALIAS esdslam_shared)
add_library(esdslam::esdslam_static ALIAS esdslam_static)

install(TARGETS esdslam_shared esdslam_static EXPORT esdslamTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS esdslam RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY include/esdslam DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY models config DESTINATION ${ESDSLAM_INSTALL_DATA_DIR})
install(FILES tools/web/index.html tools/web/viewer.css tools/web/viewer.js
        DESTINATION ${ESDSLAM_INSTALL_DATA_DIR}/tools/web)
install(DIRECTORY tools/web/node_modules/three/build tools/web/node_modules/three/examples/jsm/controls
        DESTINATION ${ESDSLAM_INSTALL_DATA_DIR}/tools/web/node_modules/three OPTIONAL
        PATTERN "*.min.js" EXCLUDE PATTERN "three.webgpu*" EXCLUDE PATTERN "three.cjs" EXCLUDE)

include(CMakePackageConfigHelpers)
set(config_dir ${CMAKE_INSTALL_LIBDIR}/cmake/esdslam)
install(EXPORT esdslamTargets NAMESPACE esdslam:: DESTINATION ${config_dir})
configure_package_config_file(cmake/esdslamConfig.cmake.in ${CMAKE_BINARY_DIR}/esdslamConfig.cmake
                              INSTALL_DESTINATION ${config_dir} PATH_VARS ESDSLAM_INSTALL_DATA_DIR)
write_basic_package_version_file(${CMAKE_BINARY_DIR}/esdslamConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/esdslamConfig.cmake ${CMAKE_BINARY_DIR}/esdslamConfigVersion.cmake
        DESTINATION ${config_dir})

set(ESDSLAM_PC_LIBS_PRIVATE "-lceres -lyaml-cpp -lspdlog -lfmt -loctomap -loctomath -lcpp-httplib -ldeflate -lpthread")
file(RELATIVE_PATH ESDSLAM_PC_PREFIX_FROM_PCDIR ${CMAKE_INSTALL_FULL_LIBDIR}/pkgconfig ${CMAKE_INSTALL_PREFIX})
configure_file(cmake/esdslam.pc.in ${CMAKE_BINARY_DIR}/esdslam.pc @ONLY)
install(FILES ${CMAKE_BINARY_DIR}/esdslam.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

set(CPACK_PACKAGE_NAME esdslam)
set(CPACK_PACKAGE_VENDOR "ESD-SLAM")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "RGB-D SLAM that stays accurate when people walk through the scene")
set(CPACK_PACKAGE_CONTACT "ESD-SLAM developers")
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libopencv-dev, libeigen3-dev, libceres-dev, libyaml-cpp-dev, libspdlog-dev, libfmt-dev, liboctomap-dev, libdeflate-dev")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_GENERATOR DEB)
include(CPack)
