// The diffuse light of the host's directional lights at N (in the lights' space): sum of color * max(N.L, 0).
// Needs the host's light prelude (baker_light_count, baker_light_direction, baker_light_color, BAKER_MAX_LIGHTS).
vec3 baker_directional_diffuse(vec3 N) {
	vec3 sum = vec3(0.0);
	for (int i = 0; i < BAKER_MAX_LIGHTS; i++) {
		if (i >= baker_light_count()) break;
		sum += baker_light_color(i) * max(dot(N, baker_light_direction(i)), 0.0);
	}
	return sum;
}
