// Fixture: CGAL outside libiaa/mesh/.
#include <CGAL/Simple_cartesian.h>
