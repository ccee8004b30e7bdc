# The sensor families this build serves, one folder per line, in the order the gateway lists
# them (the first family's first protocol is what a [[bus]] without `protocol` speaks).
# A new family is its folder plus one line here: the top-level CMakeLists.txt adds each
# folder, families/CMakeLists.txt generates the family list from it and links each family's
# tiltgate_FOLDER_family library (docs/development.md, "Adding a sensor family").
set(TILTGATE_FAMILIES
  rieker
  spectron
  modbus_rtu
)
