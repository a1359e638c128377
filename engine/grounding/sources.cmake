# The grounding capability's translation units: one list for the engine library (engine/CMakeLists.txt) and the decoder
# fuzz target (tests/fuzz/CMakeLists.txt), so that a file added here cannot be missing from either.
set(ANCHORDB_GROUNDING_SOURCES knowledge.cc furniture_graph.cc grounding.cc ambiguity.cc joint_model.cc
    orientation_prior.cc parser.cc readings.cc)
list(TRANSFORM ANCHORDB_GROUNDING_SOURCES PREPEND "${CMAKE_CURRENT_LIST_DIR}/")
