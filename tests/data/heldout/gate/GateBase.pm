// A sliding gate, in RoboTool's own notation (.pm, no package): a leaf on a horizontal
// prismatic rail along x, driven by a speed-controlled linear motor; an encoder of our own
// reports the leaf's travel.

import physmod::math::*
import physmod::joints::Prismatic
import physmod::actuators::LinearSpeedControlMotor

sensor TravelEncoder {
	input travel: real
	output reading: real
	equation reading == travel
}

pmodel GateBase {
	local link Post {
		def {
			inertial information {
				mass 20.0kg
				inertia matrix { ixx 1 ixy 0 ixz 0 iyy 1 iyz 0 izz 1 }
			}
		}
		local body Pillar {
			pose { x = 0 y = 0 z = 0.6m roll = 0 pitch = 0 yaw = 0 }
			def { box(length = 0.1m, width = 0.1m, height = 1.2m) }
		}
		jref Rail = Prismatic {
			pose { x = 0.1m y = 0 z = 0.3m roll = 0 pitch = 0 yaw = 0 }
			instantiation AXIS = (|1,0,0|)
			flexibly connected to Leaf
			aref Drive = LinearSpeedControlMotor {
				instantiation R = 1.0
				instantiation L = 0.02
				instantiation Kf = 4.0
				instantiation Ke = 4.0
				instantiation b = 1.0
				instantiation Kp = 30.0
				instantiation Ki = 60.0
				instantiation Kd = 0.0
				relation Drive.F == Rail.tau
				relation Drive.lv == Rail.v
			}
			sref Travel = TravelEncoder {
				relation Travel.travel == Rail.theta
			}
		}
	}
	local link Leaf {
		pose { x = 0.1m y = 0 z = 0.3m roll = 0 pitch = 0 yaw = 0 }
		def {
			inertial information {
				mass 5.0kg
				inertia matrix { ixx 0.1 ixy 0 ixz 0 iyy 0.1 iyz 0 izz 0.1 }
			}
		}
		local body Panel {
			def { box(length = 1.0m, width = 0.03m, height = 0.5m) }
		}
	}
}
