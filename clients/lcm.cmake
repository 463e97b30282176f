# LCM clients. wgcli (shared helpers: URL/prefix defaults, ACK waiting) is a
# static library the other clients (wgmon, wgrig, wglog: issue 4) link too.
if(TARGET wglcmtypes)
  add_library(wgcli STATIC ${CMAKE_CURRENT_SOURCE_DIR}/wgcli.c)
  target_include_directories(wgcli PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})
  target_link_libraries(wgcli PUBLIC wglcmtypes)
  add_executable(wgctl ${CMAKE_CURRENT_SOURCE_DIR}/wgctl.c)
  target_link_libraries(wgctl PRIVATE wgcli wormgear)
  install(TARGETS wgctl RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
