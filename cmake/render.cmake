# pbf_render: ROS-free headless screen-space fluid renderer (issue 4).
# GL comes only from the backends (OSMesa or EGL surfaceless): every GL function is loaded
# through the backend's getProcAddress, and libGL/libOpenGL are deliberately NOT linked
# (their global gl* symbols would shadow OSMesa's and send calls to a context-less table).
get_filename_component(PBF_RENDER_ROOT "${CMAKE_CURRENT_LIST_DIR}/.." ABSOLUTE)

find_library(PBF_OSMESA_LIBRARY NAMES OSMesa OSMesa16 OSMesa32)
find_path(PBF_OSMESA_INCLUDE_DIR GL/osmesa.h)
find_library(PBF_EGL_LIBRARY NAMES EGL)
find_path(PBF_EGL_INCLUDE_DIR EGL/egl.h)
find_path(PBF_GLCOREARB_INCLUDE_DIR GL/glcorearb.h)
find_package(PNG REQUIRED)
foreach(var PBF_OSMESA_LIBRARY PBF_OSMESA_INCLUDE_DIR PBF_EGL_LIBRARY PBF_EGL_INCLUDE_DIR
            PBF_GLCOREARB_INCLUDE_DIR)
  if(NOT ${var})
    message(FATAL_ERROR "pbf_render: ${var} not found (install libosmesa6-dev, libegl-dev "
                        "and libgl-dev, see scripts/install_deps.sh)")
  endif()
endforeach()

add_library(pbf_render
  ${PBF_RENDER_ROOT}/src/render/GlBackend.cpp
  ${PBF_RENDER_ROOT}/src/render/OsMesaBackend.cpp
  ${PBF_RENDER_ROOT}/src/render/EglBackend.cpp
  ${PBF_RENDER_ROOT}/src/render/GlFunctions.cpp
  ${PBF_RENDER_ROOT}/src/render/ShaderProgram.cpp
  ${PBF_RENDER_ROOT}/src/render/RenderTarget.cpp
  ${PBF_RENDER_ROOT}/src/render/FilterOffsets.cpp
  ${PBF_RENDER_ROOT}/src/render/ParticleCulling.cpp
  ${PBF_RENDER_ROOT}/src/render/RenderCamera.cpp
  ${PBF_RENDER_ROOT}/src/render/RenderContext.cpp
  ${PBF_RENDER_ROOT}/src/render/SpherePass.cpp
  ${PBF_RENDER_ROOT}/src/render/DepthSmoothing.cpp
  ${PBF_RENDER_ROOT}/src/render/Shading.cpp
  ${PBF_RENDER_ROOT}/src/render/Readback.cpp
  ${PBF_RENDER_ROOT}/src/render/FluidRenderer.cpp
  ${PBF_RENDER_ROOT}/src/render/ImageWriter.cpp)
target_include_directories(pbf_render PUBLIC ${PBF_RENDER_ROOT}/include)
target_include_directories(pbf_render PRIVATE ${PBF_OSMESA_INCLUDE_DIR} ${PBF_EGL_INCLUDE_DIR}
                                              ${PBF_GLCOREARB_INCLUDE_DIR})
target_link_libraries(pbf_render PUBLIC Eigen3::Eigen
                                 PRIVATE ${PBF_OSMESA_LIBRARY} ${PBF_EGL_LIBRARY} PNG::PNG)
set_target_properties(pbf_render PROPERTIES POSITION_INDEPENDENT_CODE ON)

# Where the GLSL files live in the source tree (tests and tools; the node uses
# ros::package::getPath("pbf_ros") + "/shaders").
set(PBF_SHADER_SOURCE_DIR "${PBF_RENDER_ROOT}/shaders")

# Benchmark: ms per pass at 640x480 for dam-break blocks of particles. No ROS.
add_executable(pbf_render_bench ${PBF_RENDER_ROOT}/src/tools/render_bench.cpp)
target_link_libraries(pbf_render_bench PRIVATE pbf_render)
target_compile_definitions(pbf_render_bench PRIVATE
  PBF_SHADER_SOURCE_DIR="${PBF_SHADER_SOURCE_DIR}")

# Install the shaders with the package so ros::package::getPath finds them.
if(DEFINED CATKIN_PACKAGE_SHARE_DESTINATION)
  install(DIRECTORY ${PBF_SHADER_SOURCE_DIR}/ DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION}/shaders)
  install(TARGETS pbf_render pbf_render_bench
          ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
          LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
          RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
endif()
