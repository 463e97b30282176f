# wgsweep (issue 5): sweeps, regime maps, single-point views, PNGs (cairo).
# The plotting and output modules are their own files so wgrig can reuse
# them. -DWG_MPI=ON builds the MPI layer (OpenMPI from Debian).
option(WG_MPI "Build wgsweep with MPI (chains spread over ranks)" OFF)
pkg_check_modules(CAIRO REQUIRED IMPORTED_TARGET cairo fontconfig)
add_library(wgplot STATIC
  ${CMAKE_CURRENT_LIST_DIR}/plot.c
  ${CMAKE_CURRENT_LIST_DIR}/sweep_out.c
  ${CMAKE_CURRENT_LIST_DIR}/sweep_md.c
  ${CMAKE_CURRENT_LIST_DIR}/sweep_at.c
  ${CMAKE_CURRENT_LIST_DIR}/sweep_load.c)
target_include_directories(wgplot PUBLIC ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(wgplot PUBLIC wormgear PkgConfig::CAIRO)
if(WG_MPI)
  find_package(MPI REQUIRED COMPONENTS C)
  add_executable(wgsweep ${CMAKE_CURRENT_LIST_DIR}/wgsweep.c
                         ${CMAKE_CURRENT_LIST_DIR}/sweep_mpi.c)
  target_link_libraries(wgsweep PRIVATE wgplot MPI::MPI_C)
else()
  add_executable(wgsweep ${CMAKE_CURRENT_LIST_DIR}/wgsweep.c
                         ${CMAKE_CURRENT_LIST_DIR}/sweep_par.c)
  target_link_libraries(wgsweep PRIVATE wgplot)
endif()
install(TARGETS wgsweep RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
