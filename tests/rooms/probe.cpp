// Compiled by the Rooms.* tests (tests/rooms/CMakeLists.txt) with one room's include path: includes
// one header of another room, which must be found exactly when the room declares it may use it.
#include KFW_PROBE_HEADER
