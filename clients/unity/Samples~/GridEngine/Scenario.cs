using System;
using System.Collections.Generic;
using System.IO;
using Newtonsoft.Json.Linq;
using Toyroom.Protocol;

namespace Toyroom.Samples.GridEngine
{
    /// <summary>A grid cell (column, row).</summary>
    public struct Pt : IEquatable<Pt>
    {
        public readonly int C;
        public readonly int R;
        public Pt(int c, int r) { C = c; R = r; }
        public static Pt Of(Cell cell) { return new Pt((int)cell.Col, (int)cell.Row); }
        public static Pt Of(JToken cell) { return new Pt((int)cell["col"], (int)cell["row"]); }
        public bool Equals(Pt other) { return C == other.C && R == other.R; }
        public override bool Equals(object other) { return other is Pt && Equals((Pt)other); }
        public override int GetHashCode() { return C * 7919 + R; }
        public bool Near(Pt other) { return Math.Abs(C - other.C) + Math.Abs(R - other.R) <= 1; }
        /// <summary>The protocol's earshot in cells: within 2 cells Manhattan, walls ignored (or the same region).</summary>
        public const int EarshotCells = 2;
        public bool WithinEarshot(Pt other) { return Math.Abs(C - other.C) + Math.Abs(R - other.R) <= EarshotCells; }
        public Cell ToCell() { return new Cell { Col = C, Row = R }; }
        public override string ToString() { return "(" + C + "," + R + ")"; }
    }

    /// <summary>
    /// A scenario as <c>toyroom export-scenario</c> writes it: the protocol scene (regions with
    /// their cells, doors, locations, visibility) and the items, agents and their scripts.
    /// </summary>
    public sealed class ScenarioFile
    {
        public string Name;
        public bool RobotActs;
        public double TickSeconds;
        public int MaxTicks;
        public int SettleTicks;
        public Scene Scene;
        public JArray Items;
        public JArray Agents;
        public readonly Dictionary<Pt, string> RegionOf = new Dictionary<Pt, string>();
        public readonly HashSet<Pt> Walkable = new HashSet<Pt>();
        public readonly Dictionary<string, Location> Locations = new Dictionary<string, Location>();

        public const string Format = "toyroom-scenario/1";

        /// <summary>Read an export; an error names the file and what is wrong.</summary>
        public static ScenarioFile Read(string path)
        {
            JObject data;
            try
            {
                data = JObject.Parse(File.ReadAllText(path));
            }
            catch (Exception error)
            {
                throw new Engine.UnknownScenario("cannot read scenario " + path + ": " + error.Message);
            }
            if ((string)data["format"] != Format)
                throw new Engine.UnknownScenario(path + ": not a " + Format + " export (toyroom export-scenario)");
            var file = new ScenarioFile
            {
                Name = (string)data["name"],
                RobotActs = (string)data["robot"] == "act",
                TickSeconds = (double)data["tick_seconds"],
                MaxTicks = (int)data["max_ticks"],
                SettleTicks = (int)data["settle_ticks"],
                Scene = ToyroomJson.Read<Scene>(data["scene"]),
                Items = (JArray)data["items"],
                Agents = (JArray)data["agents"],
            };
            foreach (var region in file.Scene.Regions)
                foreach (var cell in region.Cells)
                {
                    file.RegionOf[Pt.Of(cell)] = region.Id;
                    file.Walkable.Add(Pt.Of(cell));
                }
            foreach (var door in file.Scene.Doors) file.Walkable.Add(Pt.Of(door.Cell));
            foreach (var location in file.Scene.Locations) file.Locations[location.Id] = location;
            return file;
        }

        /// <summary>A duration in the scenario's ticks, in an engine's ticks of <paramref name="engineTick"/> s.</summary>
        public int Scaled(int ticks, double engineTick)
        {
            return Math.Max(1, (int)Math.Ceiling(ticks * TickSeconds / engineTick));
        }
    }
}
