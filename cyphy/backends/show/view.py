"""``cyphy view``: a picture of the robot (PNG) drawn headless with matplotlib's Agg backend.

Every body is drawn at its pose (with the joints at the positions given by ``--set``): boxes,
cylinders and spheres as opaque polygons in one colour per link, meshes as a marker at their
origin. Each link frame is drawn as three short lines (x red, y green, z blue) and each joint
axis as a dashed magenta line through the joint origin. Links and bodies that V5 finds at the
same place with the same shape are drawn in red with their names, so that the paper's
"two rotor arms at the same coordinates" shows at a glance.

The picture is byte-identical from run to run (no date or software version in the PNG).
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass

import numpy as np

from cyphy import codes
from cyphy.model.poses import Pose
from cyphy.semantics.sdf.robot_tree import Robot, Shape, moved

UNKNOWN_JOINT = codes.code("E-VIEW-JOINT", codes.E,
                           "cyphy view --set names a joint the model does not have")
#: Camera presets: (elevation, azimuth) in degrees, as matplotlib's ``view_init`` takes them.
VIEWS = {"iso": (25.0, -60.0), "front": (0.0, -90.0), "side": (0.0, 0.0), "top": (90.0, -90.0)}
PALETTE = ("#4e79a7", "#f28e2b", "#59a14f", "#b07aa1", "#9c755f", "#76b7b2", "#edc948",
           "#bab0ac", "#ff9da7")
HIGHLIGHT = "#e0001b"
AXIS_COLOURS = ("#d62728", "#2ca02c", "#1f77b4")
BACKGROUND = "white"


@dataclass(frozen=True)
class ViewOptions:
    view: str = "iso"
    elevation: float | None = None  # degrees; overrides the preset's
    azimuth: float | None = None
    width: int = 1000  # pixels
    height: int = 800


@dataclass
class Picture:
    png: bytes
    #: Where each body's centre lands in the image (column, row from the top), by body name:
    #: what a test needs to look for the body's pixels.
    centres: dict[str, tuple[float, float]]


def render(robot: Robot, positions: dict[str, float], highlighted: set[str],
           options: ViewOptions = ViewOptions()) -> Picture:
    """Draw ``robot`` with the joints at ``positions``; ``highlighted`` holds the qualified
    names of the links and bodies to draw in red."""
    # lazy: matplotlib takes about 0.3 s to import; only a rendered view needs it
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure  # lazy: matplotlib (see above)
    from mpl_toolkits.mplot3d import proj3d  # lazy: matplotlib (see above)
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # lazy: matplotlib (see above)

    motion = moved(robot, positions)
    links = robot.links()
    figure = Figure(figsize=(options.width / 100, options.height / 100), dpi=100,
                    facecolor=BACKGROUND)
    FigureCanvasAgg(figure)  # headless; its draw() lays the figure out as savefig will
    ax = figure.add_subplot(projection="3d", facecolor=BACKGROUND)
    ax.set_proj_type("ortho")
    for pane in (ax.xaxis, ax.yaxis, ax.zaxis):
        pane.set_pane_color((1.0, 1.0, 1.0, 0.0))
    # One collection for every face, so that matplotlib sorts them all by depth; the frames
    # and axes are drawn over the bodies (computed_zorder off), never hidden inside them.
    ax.computed_zorder = False
    polygons: list[list[tuple[float, float, float]]] = []
    colours: list[str] = []
    points: list[np.ndarray] = []
    centres3: dict[str, np.ndarray] = {}
    labels: list[tuple[np.ndarray, str]] = []
    for i, link in enumerate(links.values()):
        d = motion[link.name]
        colour = PALETTE[i % len(PALETTE)]
        for shape in link.shapes:
            pose = d.compose(shape.pose)
            hot = shape.qualified in highlighted or link.qualified in highlighted
            faces = _faces(shape, pose)
            centres3[shape.name] = np.array(pose.position)
            if faces:
                points.extend(np.array(f) for f in faces)
                polygons.extend(faces)
                colours.extend([HIGHLIGHT if hot else colour] * len(faces))
            else:  # a mesh: its origin
                points.append(np.array([pose.position]))
                ax.scatter(*pose.position, marker="s", s=40, color=colour, zorder=2)
            if hot:
                labels.append((np.array(pose.position), shape.qualified))
    if polygons:
        ax.add_collection3d(Poly3DCollection(polygons, facecolors=colours, shade=True,
                                             linewidths=0.0, antialiased=False, alpha=1.0,
                                             zorder=1))
    everything = np.vstack(points) if points else np.zeros((1, 3))
    for link in links.values():
        everything = np.vstack([everything, d_position(motion[link.name], link.pose)])
    low, high = everything.min(axis=0), everything.max(axis=0)
    extent = float(max(high - low)) or 1.0
    length = 0.12 * extent
    for link in links.values():
        frame = motion[link.name].compose(link.pose)
        origin = np.array(frame.position)
        rotation = np.array(frame.rotation)
        for k in range(3):
            tip = origin + length * rotation[:, k]
            ax.plot(*zip(origin, tip), color=AXIS_COLOURS[k], linewidth=1.5, zorder=3)
    for joint in robot.joints():
        frame = motion[joint.parent].compose(joint.frame)
        origin = np.array(frame.position)
        for axis in joint.axes[:1]:
            direction = np.array(frame.rotation) @ axis
            ends = (origin - 0.7 * length * direction, origin + 0.7 * length * direction)
            ax.plot(*zip(*ends), color="#d000d0", linewidth=1.5, linestyle="--", zorder=4)
            ax.scatter(*origin, color="#d000d0", s=12, zorder=4)
    for where, text in labels:
        ax.text(*where, text, color=HIGHLIGHT, fontsize=8, zorder=5)
    middle = (low + high) / 2
    half = np.maximum((high - low) / 2, 0.05 * extent) * 1.1
    ax.set_xlim(middle[0] - half[0], middle[0] + half[0])
    ax.set_ylim(middle[1] - half[1], middle[1] + half[1])
    ax.set_zlim(middle[2] - half[2], middle[2] + half[2])
    ax.set_box_aspect(tuple(2 * half))
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
    elevation, azimuth = VIEWS[options.view]
    ax.view_init(elev=options.elevation if options.elevation is not None else elevation,
                 azim=options.azimuth if options.azimuth is not None else azimuth)
    title = robot.name + (" — red: V5, same shape at the same place" if labels else "")
    ax.set_title(title, fontsize=10)
    figure.tight_layout()
    figure.canvas.draw()
    centres = {}
    projection = ax.get_proj()
    for name, c in centres3.items():
        x, y, _ = proj3d.proj_transform(c[0], c[1], c[2], projection)
        column, row = ax.transData.transform((x, y))
        centres[name] = (float(column), float(options.height - row))
    out = io.BytesIO()
    figure.savefig(out, format="png", facecolor=BACKGROUND, metadata={"Software": None})
    return Picture(out.getvalue(), centres)


def d_position(motion: Pose, pose: Pose) -> np.ndarray:
    return np.array([motion.compose(pose).position])


def _faces(shape: Shape, pose: Pose) -> list[list[tuple[float, float, float]]]:
    """The shape's surface as polygons in the model frame (none for a mesh). Large faces are
    cut into small ones: matplotlib orders polygons by their centres' depth, which draws a
    large face over a small one in front of it."""
    if shape.kind == "box":
        h = [abs(v) / 2 for v in shape.size]
        faces = []
        for k in range(3):  # the two faces normal to axis k, each cut into 4 x 4
            i, j = [a for a in range(3) if a != k]
            steps = [np.linspace(-h[i], h[i], 5), np.linspace(-h[j], h[j], 5)]
            for sign in (-1.0, 1.0):
                for a0, a1 in zip(steps[0][:-1], steps[0][1:]):
                    for b0, b1 in zip(steps[1][:-1], steps[1][1:]):
                        quad = []
                        for a, b in ((a0, b0), (a1, b0), (a1, b1), (a0, b1)):
                            corner = [0.0, 0.0, 0.0]
                            corner[i], corner[j], corner[k] = a, b, sign * h[k]
                            quad.append(pose.apply(corner))
                        faces.append(quad)
        return faces
    if shape.kind == "cylinder":
        radius, half = abs(shape.size[0]), abs(shape.size[1]) / 2
        ring = [(radius * math.cos(a), radius * math.sin(a))
                for a in np.linspace(0.0, 2 * math.pi, 25)[:-1]]
        heights = np.linspace(-half, half, 5)
        sides = [[pose.apply((*ring[i], z0)), pose.apply((*ring[(i + 1) % 24], z0)),
                  pose.apply((*ring[(i + 1) % 24], z1)), pose.apply((*ring[i], z1))]
                 for i in range(24) for z0, z1 in zip(heights[:-1], heights[1:])]
        caps = [[pose.apply((0.0, 0.0, z)), pose.apply((*ring[i], z)),
                 pose.apply((*ring[(i + 1) % 24], z))] for z in (-half, half) for i in range(24)]
        return sides + caps
    if shape.kind == "sphere":
        radius = abs(shape.size[0])
        faces = []
        lats = np.linspace(-math.pi / 2, math.pi / 2, 9)
        lons = np.linspace(0.0, 2 * math.pi, 17)

        def point(lat: float, lon: float) -> tuple[float, float, float]:
            return pose.apply((radius * math.cos(lat) * math.cos(lon),
                               radius * math.cos(lat) * math.sin(lon), radius * math.sin(lat)))

        for a, b in zip(lats[:-1], lats[1:]):
            for c, d in zip(lons[:-1], lons[1:]):
                faces.append([point(a, c), point(a, d), point(b, d), point(b, c)])
        return faces
    return []
