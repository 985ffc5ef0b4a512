# SPDX-License-Identifier: LGPL-2.1-or-later
# Built-in designed scenes: glass whose caustic forms a picture, designed at
# build time by `causticd design` (docs/design.md). Nothing here is committed
# but the recipes: the photographs come from Debian's python3-skimage
# (tools/bootstrap.sh fetches the package and passes its data folder), the
# other pictures are drawn by caustic-design-targets.
#
# Per design, in the asset folder:
#   scenes/design-<name>.json        the scene (the gallery loads it)
#   meshes/design-<name>.obj         its freeform face
#   designs/design-<name>.target.png the target picture as designed
#   designs/design-<name>.report.json the designer's figures (engine SSIM, ...)
# Reports and targets live outside scenes/ so that the gallery never takes
# them for scenes.
set(CAUSTICD_DESIGN_PHOTO_DIR "" CACHE PATH
    "scikit-image's data folder (python3-skimage: .../skimage/data) with the photographs to design; empty: skip them")
set(CAUSTICD_DESIGN_FONT /usr/share/fonts/truetype/dejavu/DejaVuSans-Bold.ttf CACHE FILEPATH
    "TrueType font of the text design (fonts-dejavu-core)")
# 256 like the optics scenes: a 513^2 face is a 42 MB OBJ that the server
# takes 3 to 4 s to load and level at every start (measured: 20 s to start
# with four of them, against 5 s), for edges only a little sharper.
set(CAUSTICD_DESIGN_RESOLUTION 256 CACHE STRING "Cells per side of the built-in designs")

set(design_dir ${CAUSTIC_ASSET_DIR}/designs)
set(design_work ${CMAKE_CURRENT_BINARY_DIR}/designs)
file(MAKE_DIRECTORY ${design_dir} ${design_work} ${CAUSTIC_ASSET_DIR}/meshes ${CAUSTIC_ASSET_DIR}/scenes)
set(CAUSTIC_DESIGNED_SCENES "" CACHE INTERNAL "ids of the built-in designed scenes")
set(designed_ids "")
set(design_outputs "")

# caustic_design(ID PICTURE NAME DESCRIPTION [FLAGS...]): designs one scene
# from PICTURE. Lens 100 mm, screen 200 mm below (the designer's defaults, a
# relief of a few millimetres and slopes under 20 degrees on every picture
# here); FLAGS go to `causticd design` as they are (--colour).
function(caustic_design id picture name description)
  set(params --size 100 --focus 200 --resolution ${CAUSTICD_DESIGN_RESOLUTION} ${ARGN})
  # The Makefile generator does not rerun a command whose arguments changed:
  # the parameters go into a file that changes with them, and the command
  # depends on it.
  file(CONFIGURE OUTPUT ${design_work}/${id}.params CONTENT "${picture}\n${params}\n${name}\n${description}\n")
  set(target ${design_dir}/${id}.target.png)
  set(mesh ${CAUSTIC_ASSET_DIR}/meshes/${id}.obj)
  set(scene ${CAUSTIC_ASSET_DIR}/scenes/${id}.json)
  set(report ${design_dir}/${id}.report.json)
  # COMMAND causticd orders the build after the binary without rerunning on
  # each relink; the design library's archive changes only when the designer
  # does, so that is the file-level dependency.
  add_custom_command(
    OUTPUT ${target} ${mesh} ${scene} ${report}
    # causticd design writes into existing folders only; these may have been cleaned since configuring.
    COMMAND ${CMAKE_COMMAND} -E make_directory ${design_dir} ${CAUSTIC_ASSET_DIR}/meshes ${CAUSTIC_ASSET_DIR}/scenes
    COMMAND ${CMAKE_COMMAND} -E copy ${picture} ${target}
    COMMAND causticd design --target ${target} -o ${mesh} --scene-out ${scene} --report ${report}
            --name ${name} --description ${description} ${params}
    DEPENDS ${picture} ${design_work}/${id}.params $<TARGET_FILE:caustic_design>
    COMMENT "Designing the ${id} scene (${CAUSTICD_DESIGN_RESOLUTION}^2 cells)"
    VERBATIM)
  set(designed_ids ${designed_ids} ${id} PARENT_SCOPE)
  set(design_outputs ${design_outputs} ${target} ${mesh} ${scene} ${report} PARENT_SCOPE)
endfunction()

# Photographs (descriptions and licences: assets/README.md).
set(photos
    "design-cat|chelsea.png|Chelsea the cat|The face of Chelsea the cat, thrown as light by a 100 mm freeform acrylic slab onto a screen 200 mm below."
    "design-astronaut|astronaut.png|Astronaut portrait|NASA's portrait of astronaut Eileen Collins, formed by light refracted through a 100 mm freeform acrylic slab onto a screen 200 mm below."
    "design-coffee|coffee.png|A cup of coffee, in colour|An espresso on its red saucer in colour: the slab's shape throws the light, a tint on its face gives each part of the picture its colour.|--colour")
set(photo_dir_ok FALSE)
if(CAUSTICD_DESIGN_PHOTO_DIR AND EXISTS ${CAUSTICD_DESIGN_PHOTO_DIR}/chelsea.png)
  set(photo_dir_ok TRUE)
endif()
set(CAUSTIC_DESIGN_PHOTOS ${photo_dir_ok} CACHE INTERNAL "whether the photographic designs are built")
if(photo_dir_ok)
  foreach(entry IN LISTS photos)
    string(REPLACE "|" ";" fields "${entry}")
    list(GET fields 0 id)
    list(GET fields 1 file)
    list(GET fields 2 name)
    list(GET fields 3 description)
    set(flags "")
    list(LENGTH fields count)
    if(count GREATER 4)
      list(SUBLIST fields 4 -1 flags)
    endif()
    caustic_design(${id} ${CAUSTICD_DESIGN_PHOTO_DIR}/${file} "${name}" "${description}" ${flags})
  endforeach()
else()
  message(WARNING "CAUSTICD_DESIGN_PHOTO_DIR is not set to scikit-image's data folder (holding chelsea.png): "
                  "the photographic designed scenes are skipped. tools/bootstrap.sh fetches python3-skimage and sets it.")
endif()

# Drawn pictures.
set(drawn ${design_work}/logo.png)
add_custom_command(
  OUTPUT ${design_work}/logo.png
  COMMAND caustic-design-targets --size 512 logo -o ${design_work}/logo.png
  DEPENDS caustic-design-targets
  COMMENT "Drawing the logo target"
  VERBATIM)
caustic_design(design-logo ${design_work}/logo.png "Ring and star"
               "A ring around a five-pointed star over a bar, drawn in light by a 100 mm freeform acrylic slab: thin lines on black, the hardest kind of picture for a caustic.")
if(EXISTS ${CAUSTICD_DESIGN_FONT})
  add_custom_command(
    OUTPUT ${design_work}/text.png
    COMMAND caustic-design-targets --size 512 text -o ${design_work}/text.png
            --font ${CAUSTICD_DESIGN_FONT} --line Hello --line light
    DEPENDS caustic-design-targets ${CAUSTICD_DESIGN_FONT}
    COMMENT "Drawing the text target"
    VERBATIM)
  caustic_design(design-text ${design_work}/text.png "Hello, light"
                 "The words \"Hello light\" in DejaVu Sans Bold, written in light by a 100 mm freeform acrylic slab onto a screen 200 mm below.")
else()
  message(WARNING "CAUSTICD_DESIGN_FONT (${CAUSTICD_DESIGN_FONT}) does not exist: the text design is skipped "
                  "(install fonts-dejavu-core).")
endif()

set(CAUSTIC_DESIGNED_SCENES ${designed_ids} CACHE INTERNAL "ids of the built-in designed scenes")
add_custom_target(designs ALL DEPENDS ${design_outputs})
