// Linear blend skinning in the vertex shader (facet.scene.skinned): each vertex moves by
// sum_k w_k J_{j_k}, up to 4 joints (SKIN_8: 8). The joints' matrices come as texels, the
// three rows of joint j's 3x4 matrix at (0..2, j) of u_joints (RGBA32F).
uniform sampler2D u_joints;
in uvec4 in_joints0;
in vec4 in_weights0;
#ifdef SKIN_8
in uvec4 in_joints1;
in vec4 in_weights1;
#endif

mat4 joint_matrix(uint j) {
    int row = int(j);
    return transpose(mat4(texelFetch(u_joints, ivec2(0, row), 0),
                          texelFetch(u_joints, ivec2(1, row), 0),
                          texelFetch(u_joints, ivec2(2, row), 0), vec4(0.0, 0.0, 0.0, 1.0)));
}

mat4 skin_matrix() {
    mat4 m = in_weights0.x * joint_matrix(in_joints0.x) + in_weights0.y * joint_matrix(in_joints0.y)
           + in_weights0.z * joint_matrix(in_joints0.z) + in_weights0.w * joint_matrix(in_joints0.w);
#ifdef SKIN_8
    m += in_weights1.x * joint_matrix(in_joints1.x) + in_weights1.y * joint_matrix(in_joints1.y)
       + in_weights1.z * joint_matrix(in_joints1.z) + in_weights1.w * joint_matrix(in_joints1.w);
#endif
    return m;
}
