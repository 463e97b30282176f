# LCM clients of issue 4: wgmon (live dashboard), wglog (log export and
# summary), wgrig (automated rig sweep), wgspy (lcm-spy launcher). They link
# wgcli (URL/prefix defaults, ACK waiting) from lcm.cmake and, for wgrig, the
# analysis and plotting code of the offline sweep (wgplot, sweep.cmake).
if(TARGET wgcli)
  add_executable(wgmon ${CMAKE_CURRENT_LIST_DIR}/wgmon.c)
  target_link_libraries(wgmon PRIVATE wgcli wormgear m)
  install(TARGETS wgmon RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  if(EXISTS ${CMAKE_CURRENT_LIST_DIR}/wglog.c)
    add_executable(wglog ${CMAKE_CURRENT_LIST_DIR}/wglog.c)
    target_link_libraries(wglog PRIVATE wglcmtypes m)
    install(TARGETS wglog RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  endif()
  if(TARGET wgplot AND EXISTS ${CMAKE_CURRENT_LIST_DIR}/wgrig.c)
    add_executable(wgrig ${CMAKE_CURRENT_LIST_DIR}/wgrig.c ${CMAKE_CURRENT_LIST_DIR}/rig_point.c)
    target_link_libraries(wgrig PRIVATE wgcli wgplot wormgear m)
    install(TARGETS wgrig RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  endif()
endif()
install(PROGRAMS ${CMAKE_CURRENT_LIST_DIR}/wgspy DESTINATION ${CMAKE_INSTALL_BINDIR})
