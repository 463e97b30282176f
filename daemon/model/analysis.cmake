# Analysis (issue 5): regime detection, Lyapunov exponents, Floquet
# multipliers, sweeps with continuation and the transitions table. Part of
# the model library so the daemon's STATUS, wgsweep and wgrig share one
# implementation. Chains run on POSIX threads.
find_package(Threads REQUIRED)
target_sources(wgmodel PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/wg_regime.c
  ${CMAKE_CURRENT_LIST_DIR}/wg_floquet.c
  ${CMAKE_CURRENT_LIST_DIR}/wg_sweep.c
  ${CMAKE_CURRENT_LIST_DIR}/wg_transitions.c)
target_link_libraries(wgmodel PUBLIC Threads::Threads)
