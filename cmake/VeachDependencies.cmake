# Finds the Debian 12 packages Veach builds on, as imported targets, and repairs the two
# package configs that are broken on Debian 12.

find_package(embree 3.13 REQUIRED)
find_package(TBB REQUIRED)
find_package(TinyGLTF REQUIRED)
find_package(Threads REQUIRED)

# OpenImageIO's config lists /usr/include/opencv4 among its include directories even when
# libopencv-dev is absent, which fails CMake's generate step.
find_package(OpenImageIO REQUIRED)
get_target_property(_veach_oiio_inc OpenImageIO::OpenImageIO INTERFACE_INCLUDE_DIRECTORIES)
list(FILTER _veach_oiio_inc EXCLUDE REGEX "opencv4")
set_target_properties(OpenImageIO::OpenImageIO PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_veach_oiio_inc}")

# OpenColorIO's config is installed under /usr/share/cmake with a wrong prefix; pkg-config's
# file is right.
find_package(PkgConfig REQUIRED)
pkg_check_modules(VEACH_OCIO REQUIRED IMPORTED_TARGET OpenColorIO)
if(NOT TARGET OpenColorIO::OpenColorIO)
  add_library(OpenColorIO::OpenColorIO ALIAS PkgConfig::VEACH_OCIO)
endif()
