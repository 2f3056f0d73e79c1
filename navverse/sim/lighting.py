"""Light on the renderer's hits: sun with shadows, sky, room lamps, then exposure and tone mapping.

:class:`Lighting` turns the albedo (linear RGB) of each hit point into radiance: the sun's irradiance
times the cosine to the sun where a shadow ray towards it leaves the scene unblocked, the sky's light
from above and the ground's from below blended by the normal's height (in the open), and inside an
indoor room its lamp (cosine, inverse square, a shadow ray) and the light the room bounces around.
Pixels that hit nothing show the sky (a gradient with a glow around the sun) in scenes with a sky.
Outdoors, far surfaces fade towards the horizon's colour (aerial perspective). The frame is then
exposed automatically (its log-average luminance brought to a middle grey, with the look's
compensation), tone mapped with a filmic curve and encoded as sRGB. The per-hit loops are compiled
(:mod:`navverse.sim.shade_kernels`); everything is deterministic, with no state between frames.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from navverse.look.rooms import RoomLights
from navverse.look.settings import LookSettings
from navverse.look.sky import SunSky, sun_sky
from navverse.scene.colors import linear_to_srgb
from navverse.sim import shade_kernels as kernels
from navverse.sim.raycast import TriangleCaster

__all__ = ["MIDDLE_GREY", "ImageHits", "Lighting"]

MIDDLE_GREY = 0.2
"""Exposed value the log-average luminance of a frame is brought to (before tone mapping)."""
_EXPOSURE_RANGE = (0.08, 12.0)  # automatic exposure stays within these factors
_LAMP_COLOR = np.array([1.0, 0.92, 0.8], dtype=np.float32)  # warm white
_BOUNCE = 0.28  # share of a room lamp's light that reaches everything in the room, bounced
_LAMP_REACH = 2.0  # meters at which a lamp gives its full strength; farther, it falls off as 1/d^2
_HAZE_DISTANCE = 450.0  # meters of aerial perspective: 1 - exp(-d / distance) towards the horizon
_ENCODE_STEPS = 4096
_EXPOSURE_STRIDE = 5  # the exposure reads every fifth measured pixel (odd: no alignment with rows)


class ImageHits(NamedTuple):
    """Where a frame's hits are: their flat pixel indices ``(K,)`` in an image `width` x `height`, and
    the face each hit (``(K,)``)."""

    pixels: np.ndarray
    face: np.ndarray
    width: int
    height: int


def _encode_table() -> np.ndarray:
    """sRGB bytes of tone-mapped values ``k / (_ENCODE_STEPS - 1)``."""
    return linear_to_srgb(np.linspace(0.0, 1.0, _ENCODE_STEPS))


class Lighting:
    """The light of one look on one scene, for a renderer that casts in a local frame.

    Parameters
    ----------
    settings : LookSettings
        Time of day, intensities, exposure, shadows.
    rooms : RoomLights
        The scene's rooms and their lamps.
    latitude_deg : float or None
        The scene's latitude (its map origin), if known.
    caster : TriangleCaster
        The renderer's ray caster (in the local frame), for shadow rays.
    origin : ndarray, shape (3,)
        World point of the local frame's origin.
    sky : bool
        Whether rays that hit nothing see the sky and far surfaces fade into haze (outdoor scenes).
    threads : int
        Threads for the shadow rays; 0 uses every core.
    """

    def __init__(
        self,
        settings: LookSettings,
        *,
        rooms: RoomLights,
        latitude_deg: float | None,
        caster: TriangleCaster,
        origin: np.ndarray,
        sky: bool,
        threads: int = 0,
    ) -> None:
        self.settings = settings
        self.sun_sky: SunSky = sun_sky(settings, latitude_deg=latitude_deg)
        self.rooms = rooms
        self._caster = caster
        self._origin = np.asarray(origin, dtype=np.float64)
        self._sky = bool(sky)
        self._threads = int(threads)
        self._lamps = (self.rooms.lamps - self._origin).astype(np.float32)
        self._encode = _encode_table()
        ss = self.sun_sky
        self._sun_up = bool(ss.sun_direction[2] > 0.0 and ss.sun_color.max() > 0.0)
        self._sun = ss.sun_direction.astype(np.float32)
        self._sun_color = ss.sun_color.astype(np.float32)
        self._sky_light = ss.sky_light.astype(np.float32)
        self._ground_light = ss.ground_light.astype(np.float32)
        self._horizon = ss.sky_horizon.astype(np.float32)

    def irradiance(
        self,
        points: np.ndarray,
        normals: np.ndarray,
        depth: np.ndarray,
        room: np.ndarray,
        *,
        image: ImageHits | None = None,
    ) -> np.ndarray:
        """The light ``(3, K)`` falling on `K` hits (linear RGB irradiance).

        Parameters
        ----------
        points : ndarray of float32, shape (K, 3)
            Hit points in the local frame.
        normals : ndarray of float32, shape (K, 3)
            Unit normals turned towards the camera.
        depth : ndarray of float32, shape (K,)
            Distance along the optical axis (lifts the shadow rays' origins).
        room : ndarray of int32, shape (K,)
            The room each hit is in (``-1``: in the open), as ``SceneLook.room_of`` tells. Indoors only
            the room's lamp lights a hit; the sun and the sky light the open.
        image : ImageHits, optional
            Where the hits are in an image: shadow rays are then cast on a checkerboard, and a hit on
            an odd square whose four neighbours on the same face agree takes their shadow.
        """
        light = np.empty((3, len(points)), dtype=np.float32)
        sun_cosine = np.empty(len(points), dtype=np.float32)
        room = np.ascontiguousarray(room, dtype=np.int32)
        facing = kernels.open_air_light(
            normals, room, self._sky_light, self._ground_light, self._sun, self._sun_up, light, sun_cosine
        )
        if facing:
            lit = np.flatnonzero(sun_cosine)
            if self.settings.shadows:
                key = None if image is None else image.face
                blocked = self._occluded(
                    points, normals, depth, lit, self._sun[None, :], far=np.inf, key=key, image=image
                )
            else:
                blocked = np.zeros(len(lit), dtype=bool)
            kernels.add_sun(light, lit, blocked, sun_cosine, self._sun_color)
        if (room >= 0).any():
            self._add_lamps(light, points, normals, depth, room, image=image)
        return light

    def shade(
        self,
        radiance: np.ndarray,
        hits: np.ndarray,
        albedo: np.ndarray,
        light: np.ndarray,
        depth: np.ndarray,
        reflect: np.ndarray,
    ) -> None:
        """Write the radiance of `K` hits into the pixels `hits` of `radiance` ``(3, P)``: `albedo` times
        `light` (:meth:`irradiance`), plus the sky that glass and water mirror, faded with distance into
        the horizon's haze outdoors.

        Parameters
        ----------
        radiance : ndarray of float32, shape (3, P)
            The frame's radiance, written at `hits`.
        hits : ndarray of int, shape (K,)
            Pixel indices of the hits.
        albedo, light : ndarray of float32, shape (3, K)
            Linear RGB reflectance and irradiance.
        depth : ndarray of float32, shape (K,)
            Distance along the optical axis (for the haze).
        reflect : ndarray of float32, shape (K,)
            Share of the sky each hit mirrors: it adds that much of the horizon's radiance (the sky a
            vertical pane mostly sees).
        """
        haze = _HAZE_DISTANCE if self._sky else 0.0
        kernels.split(
            kernels.shade_hits, len(hits), radiance, hits, albedo, light, depth, reflect, self._horizon, haze,
            parts=self._threads,
        )  # fmt: skip

    def _add_lamps(
        self,
        light: np.ndarray,
        points: np.ndarray,
        normals: np.ndarray,
        depth: np.ndarray,
        room: np.ndarray,
        *,
        image: ImageHits | None,
    ) -> None:
        """Add each indoor hit's room lamp (direct, shadowed) and the room's bounced light to `light`."""
        strength = float(self.settings.room_light)
        direct = np.empty(len(points), dtype=np.float32)
        to_lamp = np.empty((len(points), 3), dtype=np.float32)
        kernels.lamp_light(points, normals, room, self._lamps, strength, _LAMP_REACH, direct, to_lamp)
        shadowed = np.flatnonzero(direct) if self.settings.shadows else np.zeros(0, dtype=np.int64)
        key = None if image is None else image.face.astype(np.int64) * (len(self._lamps) + 1) + room + 1
        blocked = self._occluded(points, normals, depth, shadowed, to_lamp, far=1.0, key=key, image=image)
        kernels.add_lamps(light, room, direct, shadowed, blocked, strength * _BOUNCE, _LAMP_COLOR)

    def _occluded(
        self,
        points: np.ndarray,
        normals: np.ndarray,
        depth: np.ndarray,
        which: np.ndarray,
        directions: np.ndarray,
        *,
        far: float,
        key: np.ndarray | None = None,
        image: ImageHits | None = None,
    ) -> np.ndarray:
        """Whether a ray from each hit `which` (lifted off its surface) along its direction
        (``(K, 3)``, one per hit, or ``(1, 3)`` for all) meets geometry before parameter `far` (1.0:
        the end of an unnormalised direction to a lamp). With an `image` and a `key` per hit, rays are
        cast on a checkerboard's even squares, then where the odd squares' neighbours of the same key
        disagree."""
        if image is None or key is None or len(which) == 0:
            return self._cast_shadows(points, normals, depth, which, directions, far=far)
        even = kernels.even_pixels(image.pixels, which, image.width)
        first = np.flatnonzero(even)
        blocked = self._cast_shadows(points, normals, depth, which[first], directions, far=far)
        state, undecided = kernels.checker_fill(
            image.pixels, which, key, even, blocked, image.width, image.height
        )
        state[undecided] = self._cast_shadows(points, normals, depth, which[undecided], directions, far=far)
        return state.astype(bool)

    def _cast_shadows(
        self,
        points: np.ndarray,
        normals: np.ndarray,
        depth: np.ndarray,
        which: np.ndarray,
        directions: np.ndarray,
        *,
        far: float,
    ) -> np.ndarray:
        """Whether each shadow ray of :meth:`_occluded` meets geometry (one ray per hit)."""
        if len(which) == 0:
            return np.zeros(0, dtype=bool)
        rays = kernels.lifted_rays(
            points, normals, depth, which, np.ascontiguousarray(directions, np.float32)
        )
        tfar = np.inf if not np.isfinite(far) else float(far) * (1.0 - 1e-3)
        return self._caster.occluded(rays, tfar=tfar)

    def sky(self, radiance: np.ndarray, pixels: np.ndarray, rays: np.ndarray) -> None:
        """Write the sky's radiance into the `pixels` of `radiance` ``(3, P)`` by the directions of their
        rays (``rays`` ``(P, 6)``, world z up): a gradient from the horizon up, a glow round the sun."""
        ss = self.sun_sky
        kernels.split(
            kernels.sky_pixels, len(pixels), radiance, pixels, rays, self._horizon,
            ss.sky_zenith.astype(np.float32), self._sun, self._sun_color, self._sun_up, parts=self._threads,
        )  # fmt: skip

    def encode(self, radiance: np.ndarray, *, measured: np.ndarray | None = None) -> np.ndarray:
        """sRGB bytes ``(P, 3)`` of radiance ``(3, P)``: exposed, tone mapped, encoded.

        Parameters
        ----------
        radiance : ndarray of float32, shape (3, P)
            The frame's radiance, every pixel.
        measured : ndarray of bool, shape (P,), optional
            Pixels the automatic exposure measures (default: all; every
            :data:`_EXPOSURE_STRIDE`-th of them is read).
        """
        if measured is None:
            measured = np.arange(radiance.shape[1])
        pixels = np.flatnonzero(measured) if measured.dtype == bool else measured
        average = kernels.log_average_luma(radiance, pixels, _EXPOSURE_STRIDE)
        if not np.isfinite(average):
            average = MIDDLE_GREY
        scale = np.clip(MIDDLE_GREY / average, *_EXPOSURE_RANGE) * 2.0**self.settings.exposure_ev
        out = np.empty((radiance.shape[1], 3), dtype=np.uint8)
        kernels.split(
            kernels.encode_pixels, radiance.shape[1], radiance, float(scale), self._encode, out,
            parts=self._threads,
        )  # fmt: skip
        return out
