# Every dependency comes from a Debian 12 package and is found through its CMake package.
find_package(glm CONFIG REQUIRED)
find_package(OpenEXR CONFIG REQUIRED)
find_package(OpenImageIO CONFIG REQUIRED)
find_package(flann CONFIG REQUIRED)
find_package(embree 3 CONFIG REQUIRED)  # the renderer's BVH
# OBJ meshes of scenes. tinyobjloader is one header: libbtf compiles its implementation (obj_mesh.cpp)
# and takes only the header's folder from the package, not the prebuilt library.
find_package(tinyobjloader CONFIG REQUIRED)
find_package(nanoflann CONFIG REQUIRED) # a peer of the photon map's kd-tree, in benchmarks only
find_package(TBB CONFIG REQUIRED)
find_package(Boost 1.74 REQUIRED)   # header-only Boost.Math (chi-square distribution)
find_package(nlohmann_json CONFIG REQUIRED)
find_package(CLI11 CONFIG REQUIRED)
find_package(zstd CONFIG REQUIRED)
find_package(Eigen3 CONFIG REQUIRED)  # per-view PCA baseline (Ceres depends on it anyway)
find_package(ZLIB REQUIRED)           # CRC-32 of .btfz sections
find_package(Ceres CONFIG REQUIRED)   # least-squares fits of analytic models (fit/)
find_package(Qhull CONFIG REQUIRED)   # spherical Delaunay triangulations of measured directions (core/)

# Debian's OpenImageIO package lists /usr/include/opencv4 as an include directory although OpenCV
# is not a dependency of the -dev package. Filter the missing folder out instead of installing OpenCV.
foreach(prop INTERFACE_INCLUDE_DIRECTORIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES)
  get_target_property(dirs OpenImageIO::OpenImageIO ${prop})
  if(dirs)
    list(FILTER dirs EXCLUDE REGEX "opencv4")
    set_target_properties(OpenImageIO::OpenImageIO PROPERTIES ${prop} "${dirs}")
  endif()
endforeach()

if(BTF_BUILD_TESTS)
  find_package(GTest CONFIG REQUIRED)
endif()
if(BTF_BUILD_BENCHMARKS)
  find_package(benchmark CONFIG REQUIRED)
endif()
