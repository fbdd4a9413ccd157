// open(s): the rail's demanded speed; shut(): at rest. atOpen: the leaf 0.6 m along the
// rail or more; atShut: within 0.02 m of the post.

map GateMapping dmodel GateSoftware to pmodel GateBase {
	operation open {
		equation Post::Rail::Drive.dls == s
	}
	operation shut {
		equation Post::Rail::Drive.dls == 0
	}
	input event atOpen {
		predicate Post::Rail::Travel.reading >= 0.6
	}
	input event atShut {
		predicate Post::Rail::Travel.reading <= 0.02
	}
}
