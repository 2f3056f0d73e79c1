"""Write the real-city scene recipes (recipes/scenes/real-cities/) from the shipped OSM extracts.

    python scripts/real_city_recipes.py [--check]

For each extract of :data:`CITIES`, its best non-overlapping 500 m windows (``navverse city windows``'
ranking; the data's extent when the file is smaller) become recipes ``<city>-<n>.yaml``, each a
manual target built by name (``navverse build berlin-1``) or as a link of navverse-full. ``--check``
only says whether the recipes on disk are those this script writes (exit 1 if not).
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass
from pathlib import Path

from navverse.city.osm.windows import WindowRank, rank_windows

PROJECT = Path(__file__).resolve().parents[1]
FOLDER = PROJECT / "recipes" / "scenes" / "real-cities"
RAW = PROJECT / "data" / "raw" / "osm"
SIZE = 500.0


@dataclass(frozen=True)
class City:
    """Windows to take from one extract."""

    name: str
    file: str
    place: str
    continent: str
    windows: int


CITIES = (
    City("berlin", "berlin-mitte.osm.xml.gz", "Berlin, Germany (Mitte)", "Europe", 3),
    City("porto", "porto-downtown.osm.pbf", "Porto, Portugal (downtown)", "Europe", 2),
    City("munich", "munich-altstadt.osm.pbf", "Munich, Germany (Altstadt)", "Europe", 2),
    City("london", "london-farringdon.osm.pbf", "London, UK (Farringdon, St Paul's)", "Europe", 2),
    City("london-moorgate", "london-moorgate.osm.pbf", "London, UK (Moorgate)", "Europe", 1),
    City("le-havre", "le-havre-centre.osm.xml.gz", "Le Havre, France (centre)", "Europe", 2),
    City("monaco", "monaco-2022.osm.pbf", "Monaco", "Europe", 2),
    City("krems", "krems-2013.osm.gz", "Krems an der Donau, Austria (old town)", "Europe", 1),
    City("heidelberg", "heidelberg-altstadt.osm.pbf", "Heidelberg, Germany (Altstadt)", "Europe", 2),
    City("aberdeen", "aberdeen-centre.osm.gz", "Aberdeen, UK (centre)", "Europe", 1),
    City("vaduz", "vaduz-centre.osm.pbf", "Vaduz, Liechtenstein (centre)", "Europe", 1),
    City("stockholm", "stockholm-sodermalm.osm.pbf", "Stockholm, Sweden (Sodermalm)", "Europe", 1),
    City("oslo", "oslo-skoyen.osm.pbf", "Oslo, Norway (Skoyen)", "Europe", 1),
    City("leeds", "leeds-cycleway.osm", "Leeds, UK (city centre east)", "Europe", 1),
    City("essen", "essen-south.osm.xml.gz", "Essen, Germany (south of the centre)", "Europe", 1),
    City("chiang-mai", "chiang-mai-nimman.osm.xml.gz", "Chiang Mai, Thailand (Nimmanhaemin)", "Asia", 2),
    City("bishkek", "bishkek-centre.osm.xml.gz", "Bishkek, Kyrgyzstan (centre)", "Asia", 2),
    City("taichung", "taichung-tunghai.osm.xml.gz", "Taichung, Taiwan (Xitun)", "Asia", 2),
    City("ho-chi-minh", "ho-chi-minh-tan-dinh.osm", "Ho Chi Minh City, Vietnam (Tan Dinh)", "Asia", 2),
    City("bengaluru", "bangalore-kr-circle.osm.xml.gz", "Bengaluru, India (K.R. Circle)", "Asia", 2),
    City("suwon", "suwon-ajou.osm", "Suwon, South Korea (Ajou University)", "Asia", 1),
    City("singapore", "singapore-bayfront.osm.pbf", "Singapore (Bayfront)", "Asia", 1),
    City("new-york", "nyc-lower-east-side.osm.pbf", "New York, USA (Lower East Side)", "North America", 2),
    City("boston", "boston-beacon-hill.osm.pbf", "Boston, USA (Beacon Hill)", "North America", 1),
    City("baltimore", "baltimore-east.osm.pbf", "Baltimore, USA (east side)", "North America", 2),
    City("seattle", "seattle-northgate.osm", "Seattle, USA (Northgate)", "North America", 1),
    City(
        "seattle-u-district",
        "seattle-i5-exit-ramp.osm",
        "Seattle, USA (University District)",
        "North America",
        1,
    ),
    City("oakland", "west-oakland.osm", "Oakland, USA (West Oakland)", "North America", 1),
    City("aguascalientes", "aguascalientes.osm", "Aguascalientes, Mexico", "North America", 1),
    City("lima", "lima-unmsm.osm", "Lima, Peru (UNMSM)", "South America", 2),
    City("nairobi", "nairobi-westlands.osm", "Nairobi, Kenya (Westlands)", "Africa", 2),
    City("sydney", "sydney-sydenham.osm.pbf", "Sydney, Australia (Sydenham)", "Oceania", 2),
)
"""The extracts and how many windows of each: 50 windows of 30 cities on six continents."""


def _recipe(city: City, window: WindowRank) -> str:
    lat, lon = window.center
    east, north = window.size_m
    return (
        "# A real city (written by scripts/real_city_recipes.py): built by name\n"
        f"# (navverse build {city.name}-{window.rank}) or as a link of navverse-full; not by make scenes.\n"
        "description: >\n"
        f"  {city.place}, {city.continent}: a {east:.0f} m x {north:.0f} m window of {city.file}\n"
        f"  (OpenStreetMap, ODbL) with {window.buildings} buildings, {window.pois} POIs and"
        f" {window.street_km:.1f} km of streets.\n"
        "extends: outdoor-city\n"
        "manual: true\n"
        "stages:\n"
        "  osm_city:\n"
        f"    source: ../../../data/raw/osm/{city.file}\n"
        f"    center: [{lat:.6f}, {lon:.6f}]\n"
        f"    size_m: [{east:.0f}, {north:.0f}]\n"
    )


def recipes() -> dict[str, str]:
    """``{file name: text}`` of every real-city recipe."""
    found: dict[str, str] = {}
    for city in CITIES:
        ranking = rank_windows(RAW / city.file, size_m=SIZE, top=city.windows)
        if len(ranking.windows) < city.windows:
            raise SystemExit(f"{city.file} has {len(ranking.windows)} windows, not {city.windows}")
        for window in ranking.windows:
            found[f"{city.name}-{window.rank}.yaml"] = _recipe(city, window)
    return found


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--check", action="store_true", help="only compare with the recipes on disk")
    args = parser.parse_args()
    wanted = recipes()
    present = (
        {p.name: p.read_text(encoding="utf-8") for p in FOLDER.glob("*.yaml")} if FOLDER.is_dir() else {}
    )
    if args.check:
        if wanted != present:
            print("recipes/scenes/real-cities differs from what the script writes", file=sys.stderr)
            return 1
        print(f"{len(wanted)} recipes up to date")
        return 0
    FOLDER.mkdir(parents=True, exist_ok=True)
    for stale in set(present) - set(wanted):
        (FOLDER / stale).unlink()
    for name, text in wanted.items():
        (FOLDER / name).write_text(text, encoding="utf-8")
    continents = {c.continent for c in CITIES}
    places = {c.place.split(",")[0] for c in CITIES}
    print(f"wrote {len(wanted)} recipes of {len(places)} cities on {len(continents)} continents to {FOLDER}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
