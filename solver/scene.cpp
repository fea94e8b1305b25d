#include "solver/scene.hpp"
// Placeholder: parsing and validation land with the scene work.
