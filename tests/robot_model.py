"""A p-model shared by the mapping tests: a motorised revolute joint, a lamp and four
indexed IR sensors, the things a platform mapping realises events and operations with."""

ROBOT = """\
package robot
import physmod::joints::Revolute
import physmod::actuators::SpeedControlMotor
import physmod::actuators::LED
import physmod::sensors::IR
import physmod::sdf::annotations::*
pmodel Robot {
  local link Base {
    def { inertial information { mass 1.0 } }
    local body B { def { box(length = 0.1, width = 0.1, height = 0.1) } }
    jref J = Revolute {
      annotation Revolute { axis = Axis { xyz = (|0,0,1|) } }
      instantiation AXIS = (|0,0,1|)
      flexibly connected to Arm
      aref M = SpeedControlMotor { relation M.T == J.tau }
    }
    aref Lamp = LED { }
  }
  local link Arm {
    pose { x = 0.5 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }
    def { inertial information { mass 0.5 } }
    local body B { def { box(length = 0.1, width = 0.1, height = 0.1) } }
    sref S = IR { index i : [0,4) }
  }
}
"""

#: The line of ``jref J`` in ``ROBOT`` (where joint diagnostics point).
JOINT_LINE = next(i for i, line in enumerate(ROBOT.splitlines(), 1) if "jref J" in line)
