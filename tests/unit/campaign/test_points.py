"""A design point's adhesion zone composed from its parts (campaign.points): start and end in the
unit given, and a part that is not a length refused naming both values."""

from types import SimpleNamespace

import pytest

from railbrake.campaign.points import point_sets
from railbrake.errors import InputError


def _study(**fixed_parts):
    return SimpleNamespace(fixed={}, fixed_parts=fixed_parts, where=lambda key: f"study.yaml: {key}")


def test_a_zone_ends_at_its_start_plus_its_length():
    sets = point_sets(_study(**{"zone.condition": "wet"}), {"zone.start": "1.5 km", "zone.length": "500 m"}, {})
    assert sets["adhesion.zones"] == [{"start": "1.5 km", "end": "2 km", "condition": "wet"}]


def test_a_zone_part_that_is_not_a_length_is_refused_with_its_value():
    with pytest.raises(InputError, match=r"study.yaml: factors: zone.start = '1500 s', zone.length = '500 m'"):
        point_sets(_study(**{"zone.condition": "wet"}), {"zone.start": "1500 s", "zone.length": "500 m"}, {})
