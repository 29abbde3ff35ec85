# The HTML page of snag-report (html.cpp) and the JavaScript it inlines.
#
# The page is one self-contained file: Chart.js and three.js (with its
# OrbitControls) from Debian's libjs-chart.js and libjs-three are copied into
# every page. They are embedded into the binary at build time, so that
# snag-report writes pages where those packages are not installed.
#
# SNAG_WITH_HTML (ON by default) needs both packages; configuring fails with a
# message naming them when a file is missing. With SNAG_WITH_HTML=OFF the
# target still builds, and write_html() throws a UsageError naming the option.
#
# Defines the static library snag_html (alias snag::html). Included from
# exporters/CMakeLists.txt:
#   include(${CMAKE_CURRENT_SOURCE_DIR}/EmbedJs.cmake)
option(SNAG_WITH_HTML "Build snag-report's HTML page (needs libjs-chart.js and libjs-three)" ON)
set(SNAG_CHART_JS /usr/share/javascript/chart.js/chart.min.js CACHE FILEPATH "Chart.js 3 (libjs-chart.js)")
set(SNAG_THREE_JS /usr/share/javascript/three/three.min.js CACHE FILEPATH "three.js (libjs-three)")
set(SNAG_THREE_ORBIT_CONTROLS_JS /usr/share/javascript/three/examples/js/controls/OrbitControls.js
    CACHE FILEPATH "three.js OrbitControls, the non-module build (libjs-three)")

set(snag_html_dir ${CMAKE_CURRENT_LIST_DIR})
set(snag_html_assets
  page_js=${snag_html_dir}/html_page.js
  page_css=${snag_html_dir}/html_page.css)
set(snag_html_depends ${snag_html_dir}/html_page.js ${snag_html_dir}/html_page.css)
if(SNAG_WITH_HTML)
  foreach(file SNAG_CHART_JS SNAG_THREE_JS SNAG_THREE_ORBIT_CONTROLS_JS)
    if(NOT EXISTS ${${file}})
      message(FATAL_ERROR "snag-report's HTML page inlines ${${file}}, which is missing: install "
        "Debian's libjs-chart.js and libjs-three (scripts/setup.sh does), set ${file} to the file, "
        "or configure with -DSNAG_WITH_HTML=OFF to build without the HTML page")
    endif()
  endforeach()
  list(APPEND snag_html_assets chart_js=${SNAG_CHART_JS} three_js=${SNAG_THREE_JS}
       orbit_controls_js=${SNAG_THREE_ORBIT_CONTROLS_JS})
  list(APPEND snag_html_depends ${SNAG_CHART_JS} ${SNAG_THREE_JS} ${SNAG_THREE_ORBIT_CONTROLS_JS})
endif()

# Generated at build time, so that editing html_page.js or updating the
# packages rebuilds it.
set(snag_html_generated ${CMAKE_CURRENT_BINARY_DIR}/generated/html_assets.cpp)
string(REPLACE ";" "|" snag_html_assets_arg "${snag_html_assets}")
add_custom_command(
  OUTPUT ${snag_html_generated}
  COMMAND ${CMAKE_COMMAND} "-DOUTPUT=${snag_html_generated}" "-DASSETS=${snag_html_assets_arg}"
          -P ${snag_html_dir}/embed_assets.cmake
  DEPENDS ${snag_html_depends} ${snag_html_dir}/embed_assets.cmake
  COMMENT "Embedding the HTML page's scripts and style"
  VERBATIM)

add_library(snag_html STATIC ${snag_html_dir}/html.cpp ${snag_html_dir}/html_decimation.cpp ${snag_html_generated})
add_library(snag::html ALIAS snag_html)
target_link_libraries(snag_html PUBLIC snag::report PRIVATE nlohmann_json::nlohmann_json)
target_compile_options(snag_html PRIVATE -Wall -Wextra)
