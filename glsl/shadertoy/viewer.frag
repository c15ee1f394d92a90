#version 330 core
// glslViewer / The Book of Shaders conventions around a user's own main() (facet.lab
// dialect detection): the user declares what it uses of u_resolution, u_time, u_mouse,
// u_date, u_delta, u_frame and u_tex0-u_tex3 (facet fills whichever are active), and
// writes gl_FragColor (FACET_FRAG_COLOR: mapped onto this stage's output) or its own
// `out vec4`. texture2D is texture under GLSL 3.3.
#ifdef FACET_FRAG_COLOR
out vec4 facet_FragColor;
#define gl_FragColor facet_FragColor
#endif
#define texture2D texture

FACET_USER_CODE
