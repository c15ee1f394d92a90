// Constants shared by facet's GLSL libraries.
const float PI = 3.14159265358979;
