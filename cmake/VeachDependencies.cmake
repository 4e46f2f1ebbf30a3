# Finds the Debian 12 packages Veach builds on, as imported targets, and repairs the two
# package configs that are broken on Debian 12.

find_package(embree 3.13 REQUIRED)
find_package(TBB REQUIRED)
find_package(TinyGLTF REQUIRED)
# JSON: the options table the library describes, every JSON the command writes and reads.
find_package(nlohmann_json 3.10 REQUIRED)
# The `veach` command's parser (plugins/cli), from libcli11-dev.
find_package(CLI11 2.1 REQUIRED CONFIG)
# KHR_draco_mesh_compression (importers/gltf/gltf_draco.cpp only), from libdraco-dev. Debian's
# libdraco is built with its glTF transcoder, so both libdraco.so.7 and libdraco.a carry their
# own tinygltf (another version and layout) and stb_image, exported: linked as it is, it
# interposes our tinygltf calls (invalid frees in the importer), and the archive's copy is pulled
# in by libtinygltf.so's own stb references (gcc links --as-needed here). veach_draco is
# therefore a copy of libdraco.a without the members that define any tinygltf or stb symbol;
# the codec needs none of them (a link error would say so). Link draco only through it.
find_package(draco 1.5 REQUIRED CONFIG)
# EXT_meshopt_compression (importers/gltf/gltf_meshopt.cpp): Debian's shared libmeshoptimizer.
find_package(meshoptimizer 0.18 REQUIRED CONFIG)
find_library(VEACH_DRACO_ARCHIVE libdraco.a REQUIRED)
set(_veach_draco_copy ${CMAKE_BINARY_DIR}/draco/libveach_draco.a)
if(NOT EXISTS ${_veach_draco_copy} OR ${VEACH_DRACO_ARCHIVE} IS_NEWER_THAN ${_veach_draco_copy})
  file(MAKE_DIRECTORY ${CMAKE_BINARY_DIR}/draco)
  file(COPY_FILE ${VEACH_DRACO_ARCHIVE} ${_veach_draco_copy}.tmp)
  execute_process(COMMAND ${CMAKE_AR} t ${_veach_draco_copy}.tmp OUTPUT_VARIABLE _veach_draco_members)
  foreach(_member tiny_gltf_utils.cc.o gltf_decoder.cc.o gltf_encoder.cc.o mesh_io.cc.o scene_io.cc.o)
    if(_veach_draco_members MATCHES "(^|\n)${_member}(\n|$)")
      execute_process(COMMAND ${CMAKE_AR} d ${_veach_draco_copy}.tmp ${_member} COMMAND_ERROR_IS_FATAL ANY)
    endif()
  endforeach()
  execute_process(COMMAND ${CMAKE_RANLIB} ${_veach_draco_copy}.tmp COMMAND_ERROR_IS_FATAL ANY)
  file(RENAME ${_veach_draco_copy}.tmp ${_veach_draco_copy})
endif()
add_library(veach_draco STATIC IMPORTED)
get_target_property(_veach_draco_inc draco::draco_static INTERFACE_INCLUDE_DIRECTORIES)
set_target_properties(veach_draco PROPERTIES IMPORTED_LOCATION ${_veach_draco_copy}
  INTERFACE_INCLUDE_DIRECTORIES "${_veach_draco_inc}")
find_package(Threads REQUIRED)
# Part files (.vpart) are zlib streams (renderer/film/film_part.cpp), from zlib1g-dev.
find_package(ZLIB REQUIRED)

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
