"""Light on the renderer's hits: sun with shadows, sky, room lamps, then exposure and tone mapping.

:class:`Lighting` turns the albedo (linear RGB) of each hit point into radiance: the sun's irradiance
times the cosine to the sun where a shadow ray towards it leaves the scene unblocked, the sky's light
from above and the ground's from below blended by the normal's height (in the open), and inside an
indoor room its lamp (cosine, inverse square, a shadow ray) and the light the room bounces around.
Pixels that hit nothing show the sky (a gradient with a glow around the sun) in scenes with a sky.
Outdoors, far surfaces fade towards the horizon's colour (aerial perspective). The frame is then
exposed automatically (its log-average luminance brought to a middle grey, with the look's
compensation), tone mapped with a filmic curve and encoded as sRGB. Everything is vectorised numpy,
deterministic, with no state between frames.
"""

from __future__ import annotations

import numpy as np
import open3d as o3d

from navverse.look.rooms import RoomLights
from navverse.look.settings import LookSettings
from navverse.look.sky import SunSky, sun_sky
from navverse.scene.colors import linear_to_srgb

__all__ = ["MIDDLE_GREY", "Lighting"]

MIDDLE_GREY = 0.2
"""Exposed value the log-average luminance of a frame is brought to (before tone mapping)."""
_EXPOSURE_RANGE = (0.08, 12.0)  # automatic exposure stays within these factors
_LAMP_COLOR = np.array([1.0, 0.92, 0.8], dtype=np.float32)  # warm white
_BOUNCE = 0.28  # share of a room lamp's light that reaches everything in the room, bounced
_LAMP_REACH = 2.0  # meters at which a lamp gives its full strength; farther, it falls off as 1/d^2
_HAZE_DISTANCE = 450.0  # meters of aerial perspective: 1 - exp(-d / distance) towards the horizon
_LUMA = np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)
_ENCODE_STEPS = 4096


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
    raycaster : open3d.t.geometry.RaycastingScene
        The renderer's ray-casting structure (in the local frame), for shadow rays.
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
        raycaster: o3d.t.geometry.RaycastingScene,
        origin: np.ndarray,
        sky: bool,
        threads: int = 0,
    ) -> None:
        self.settings = settings
        self.sun_sky: SunSky = sun_sky(settings, latitude_deg=latitude_deg)
        self.rooms = rooms
        self._raycaster = raycaster
        self._origin = np.asarray(origin, dtype=np.float64)
        self._sky = bool(sky)
        self._threads = int(threads)
        self._lamps = (self.rooms.lamps - self._origin).astype(np.float32)
        self._encode = _encode_table()
        ss = self.sun_sky
        self._sun_up = bool(ss.sun_direction[2] > 0.0 and ss.sun_color.max() > 0.0)
        self._sun = ss.sun_direction.astype(np.float32)

    def irradiance(
        self, points: np.ndarray, normals: np.ndarray, depth: np.ndarray, room: np.ndarray
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
        """
        settings, ss = self.settings, self.sun_sky
        indoors = room >= 0
        light = np.zeros((3, len(points)), dtype=np.float32)
        # Sky and ground light in the open: blend by the normal's height.
        up = 0.5 + 0.5 * normals[:, 2]
        open_air = ~indoors
        for c in range(3):
            light[c] = np.float32(ss.ground_light[c]) + up * np.float32(ss.sky_light[c] - ss.ground_light[c])
            light[c] *= open_air
        if self._sun_up:
            cosine = normals @ self._sun
            lit = np.flatnonzero((cosine > 0.0) & ~indoors)
            if settings.shadows and len(lit):
                lit = lit[
                    ~self._occluded(points[lit], normals[lit], depth[lit], self._sun[None, :], far=np.inf)
                ]
            for c in range(3):
                light[c, lit] += np.float32(ss.sun_color[c]) * cosine[lit]
        if indoors.any():
            self._add_lamps(light, points, normals, depth, room)
        return light

    def radiance(
        self, albedo: np.ndarray, light: np.ndarray, depth: np.ndarray, reflect: np.ndarray
    ) -> np.ndarray:
        """Radiance ``(3, K)`` of `K` hits: `albedo` times `light` (:meth:`irradiance`), plus the sky that
        glass and water mirror, faded with distance into the horizon's haze outdoors.

        Parameters
        ----------
        albedo, light : ndarray of float32, shape (3, K)
            Linear RGB reflectance and irradiance.
        depth : ndarray of float32, shape (K,)
            Distance along the optical axis (for the haze).
        reflect : ndarray of float32, shape (K,)
            Share of the sky each hit mirrors: it adds that much of the horizon's radiance (the sky a
            vertical pane mostly sees).
        """
        ss = self.sun_sky
        radiance = albedo * light
        mirrors = np.flatnonzero(reflect > 0.0)
        if len(mirrors):
            for c in range(3):
                radiance[c, mirrors] += reflect[mirrors] * np.float32(ss.sky_horizon[c])
        if self._sky:
            haze = 1.0 - np.exp(depth * np.float32(-1.0 / _HAZE_DISTANCE))
            for c in range(3):
                radiance[c] += haze * (np.float32(ss.sky_horizon[c]) - radiance[c])
        return radiance

    def _add_lamps(
        self, light: np.ndarray, points: np.ndarray, normals: np.ndarray, depth: np.ndarray, room: np.ndarray
    ) -> None:
        """Add each indoor hit's room lamp (direct, shadowed) and the room's bounced light to `light`."""
        inside = np.flatnonzero(room >= 0)
        strength = np.float32(self.settings.room_light)
        to_lamp = self._lamps[room[inside]] - points[inside]
        distance2 = np.einsum("ij,ij->i", to_lamp, to_lamp)
        cosine = np.einsum("ij,ij->i", normals[inside], to_lamp) / np.sqrt(np.maximum(distance2, 1e-6))
        direct = strength * np.maximum(cosine, 0.0) * np.minimum(1.0, np.float32(_LAMP_REACH**2) / distance2)
        if self.settings.shadows:
            facing = np.flatnonzero(direct > 0.0)
            blocked = self._occluded(
                points[inside[facing]],
                normals[inside[facing]],
                depth[inside[facing]],
                to_lamp[facing],
                far=1.0,
            )
            direct[facing[blocked]] = 0.0
        total = direct + strength * np.float32(_BOUNCE)
        for c in range(3):
            light[c, inside] += _LAMP_COLOR[c] * total

    def _occluded(
        self,
        points: np.ndarray,
        normals: np.ndarray,
        depth: np.ndarray,
        directions: np.ndarray,
        *,
        far: float,
    ) -> np.ndarray:
        """Whether a ray from each point (lifted off its surface) along its direction meets geometry
        before parameter `far` (1.0: the end of an unnormalised direction to a lamp)."""
        rays = np.empty((len(points), 6), dtype=np.float32)
        lift = (np.float32(0.01) + np.float32(4e-4) * depth)[:, None]
        rays[:, :3] = points + normals * lift
        rays[:, 3:] = directions
        tfar = np.inf if not np.isfinite(far) else float(far) * (1.0 - 1e-3)
        hit = self._raycaster.test_occlusions(
            o3d.core.Tensor(rays), tnear=0.0, tfar=tfar, nthreads=self._threads
        )
        return hit.numpy().astype(bool)

    def sky(self, directions: np.ndarray) -> np.ndarray:
        """Radiance ``(3, M)`` of the sky along unit `directions` ``(M, 3)`` (world z up)."""
        ss = self.sun_sky
        height = np.clip(directions[:, 2], 0.0, 1.0) ** np.float32(0.6)
        out = np.empty((3, len(directions)), dtype=np.float32)
        glow = np.maximum(directions @ self._sun, 0.0) ** np.float32(48.0) if self._sun_up else 0.0
        for c in range(3):
            out[c] = np.float32(ss.sky_horizon[c]) + height * np.float32(ss.sky_zenith[c] - ss.sky_horizon[c])
            out[c] += np.float32(0.35 * ss.sun_color[c]) * glow
        return out

    def encode(self, radiance: np.ndarray, *, measured: np.ndarray | None = None) -> np.ndarray:
        """sRGB bytes ``(P, 3)`` of radiance ``(3, P)``: exposed, tone mapped, encoded.

        Parameters
        ----------
        radiance : ndarray of float32, shape (3, P)
            The frame's radiance, every pixel.
        measured : ndarray of bool, shape (P,), optional
            Pixels the automatic exposure measures (default: all).
        """
        luma = _LUMA @ radiance if measured is None else _LUMA @ radiance[:, measured]
        average = float(np.exp(np.mean(np.log(np.maximum(luma, 1e-4))))) if luma.size else MIDDLE_GREY
        scale = np.clip(MIDDLE_GREY / average, *_EXPOSURE_RANGE) * 2.0**self.settings.exposure_ev
        x = radiance * np.float32(scale)
        # Filmic curve (Narkowicz's fit of the ACES reference tone map).
        mapped = x * (np.float32(2.51) * x + np.float32(0.03))
        mapped /= x * (np.float32(2.43) * x + np.float32(0.59)) + np.float32(0.14)
        np.clip(mapped, 0.0, 1.0, out=mapped)
        index = (mapped * np.float32(_ENCODE_STEPS - 1) + np.float32(0.5)).astype(np.intp)
        return np.ascontiguousarray(self._encode.take(index).T)
