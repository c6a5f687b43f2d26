using System;
using System.Collections.Generic;
using System.Linq;
using Newtonsoft.Json.Linq;
using Toyroom.Protocol;

namespace Toyroom.Samples.GridEngine
{
    /// <summary>
    /// One episode of a scenario on the grid: people and the robot move one cell per tick
    /// along shortest paths and act instantly; the protocol's state, events and statuses as
    /// the SDK's message classes. The same rules as examples/grid_engine/grid_world.py.
    /// </summary>
    public sealed class GridWorld
    {
        private static readonly Pt[] Neighbours = { new Pt(1, 0), new Pt(-1, 0), new Pt(0, 1), new Pt(0, -1) };

        private sealed class Where
        {
            public string Location;
            public string Holder;
        }

        private readonly ScenarioFile scenario;
        private readonly double tickSeconds;
        private readonly int settle;
        private readonly int maxTicks;
        private readonly List<string> agentOrder = new List<string>();
        private readonly Dictionary<string, Pt> cells = new Dictionary<string, Pt>();
        private readonly Dictionary<string, string> regions = new Dictionary<string, string>();
        private readonly Dictionary<string, List<Pt>> paths = new Dictionary<string, List<Pt>>();
        private readonly Dictionary<string, string> holding = new Dictionary<string, string>();
        private readonly Dictionary<string, bool> playing = new Dictionary<string, bool>();
        private readonly List<string> itemOrder = new List<string>();
        private readonly Dictionary<string, Where> items = new Dictionary<string, Where>();
        private readonly Dictionary<string, Person> people = new Dictionary<string, Person>();
        private readonly List<string> peopleOrder = new List<string>();
        private readonly HashSet<string> labels = new HashSet<string>();
        private readonly LinkedList<RobotCommand> queue = new LinkedList<RobotCommand>();
        private readonly HashSet<string> seenIds = new HashSet<string>();
        private HashSet<string> moved = new HashSet<string>();
        private RobotCommand running;
        private int quiet;

        public readonly long Episode;
        public readonly bool RobotActs;
        public readonly string Robot;
        public long Tick;
        public bool Done;
        public List<Event> Events = new List<Event>();
        public List<CommandStatus> Statuses = new List<CommandStatus>();

        public GridWorld(ScenarioFile scenario, long episode, double tickSeconds, bool robotActs)
        {
            this.scenario = scenario;
            this.tickSeconds = tickSeconds;
            Episode = episode;
            RobotActs = robotActs;
            foreach (JObject agent in scenario.Agents)
            {
                var id = (string)agent["id"];
                agentOrder.Add(id);
                cells[id] = Pt.Of(agent["home"]);
                regions[id] = scenario.RegionOf[cells[id]];
                paths[id] = new List<Pt>();
                holding[id] = null;
                playing[id] = false;
                if ((string)agent["kind"] == "person")
                {
                    people[id] = new Person(agent, scenario, tickSeconds);
                    peopleOrder.Add(id);
                }
                else if (Robot == null) Robot = id;
            }
            foreach (JObject item in scenario.Items)
            {
                if ((bool?)item["absent"] ?? false) continue;
                var id = (string)item["id"];
                var at = (string)item["at"];
                itemOrder.Add(id);
                if (cells.ContainsKey(at))
                {
                    items[id] = new Where { Holder = at };
                    holding[at] = id;
                }
                else items[id] = new Where { Location = at };
            }
            settle = scenario.Scaled(scenario.SettleTicks, tickSeconds);
            maxTicks = scenario.Scaled(scenario.MaxTicks, tickSeconds);
        }

        // ----- paths -----------------------------------------------------------------------

        /// <summary>Cells from <paramref name="start"/> (excluded) to the nearest goal (included); null if unreachable.</summary>
        private List<Pt> Bfs(Pt start, HashSet<Pt> goals)
        {
            if (goals.Contains(start)) return new List<Pt>();
            var came = new Dictionary<Pt, Pt>();
            var seen = new HashSet<Pt> { start };
            var frontier = new Queue<Pt>();
            frontier.Enqueue(start);
            while (frontier.Count > 0)
            {
                var cell = frontier.Dequeue();
                foreach (var d in Neighbours)
                {
                    var next = new Pt(cell.C + d.C, cell.R + d.R);
                    if (!scenario.Walkable.Contains(next) || seen.Contains(next)) continue;
                    seen.Add(next);
                    came[next] = cell;
                    if (goals.Contains(next))
                    {
                        var path = new List<Pt> { next };
                        while (came.ContainsKey(path[path.Count - 1]) && !came[path[path.Count - 1]].Equals(start))
                            path.Add(came[path[path.Count - 1]]);
                        path.Reverse();
                        return path;
                    }
                    frontier.Enqueue(next);
                }
            }
            return null;
        }

        private HashSet<Pt> PlaySpots()
        {
            return new HashSet<Pt>(scenario.Scene.Locations.Where(l => l.Play).Select(l => Pt.Of(l.Cell)));
        }

        private Location LocationAt(Pt cell)
        {
            return scenario.Scene.Locations.FirstOrDefault(l => Pt.Of(l.Cell).Equals(cell));
        }

        private Location LocationOf(string id)
        {
            Location location;
            return id != null && scenario.Locations.TryGetValue(id, out location) ? location : null;
        }

        // ----- messages --------------------------------------------------------------------

        private double Time { get { return Math.Round(Tick * tickSeconds, 9); } }

        public Event Emit(string kind, string actor)
        {
            var e = new Event { Episode = Episode, Tick = Tick, Time = Time, Kind = kind, Actor = actor };
            Events.Add(e);
            return e;
        }

        private void Status(RobotCommand command, string state, string reason = "", bool? answer = null)
        {
            Statuses.Add(new CommandStatus
            {
                Command = command.Id, Robot = command.Robot, State = state, Tick = Tick, Reason = reason, Answer = answer,
            });
        }

        private Pose PoseOf(Pt cell)
        {
            var size = scenario.Scene.CellSize;
            return new Pose { X = (cell.C + 0.5) * size, Y = (cell.R + 0.5) * size, Theta = 0.0 };
        }

        public State State()
        {
            var state = new State { Episode = Episode, Tick = Tick, Time = Time, Done = Done };
            foreach (var id in agentOrder)
            {
                var cell = cells[id];
                state.Agents.Add(new AgentState
                {
                    Id = id,
                    Pose = PoseOf(cell),
                    Velocity = new Vec2 { X = 0.0, Y = 0.0 },
                    Cell = cell.ToCell(),
                    Region = regions[id],
                    Holding = holding[id],
                    Activity = playing[id] ? Activity.Playing : moved.Contains(id) ? Activity.Moving : Activity.Idle,
                });
            }
            foreach (var id in itemOrder)
            {
                var where = items[id];
                Pt cell;
                string region;
                if (where.Holder != null)
                {
                    cell = cells[where.Holder];
                    region = regions[where.Holder];
                }
                else
                {
                    var location = LocationOf(where.Location);
                    cell = Pt.Of(location.Cell);
                    region = location.Region;
                }
                state.Items.Add(new ItemState
                {
                    Id = id, Pose = PoseOf(cell), Cell = cell.ToCell(), Region = region,
                    Location = where.Location, HeldBy = where.Holder,
                });
            }
            return state;
        }

        // ----- shared actions --------------------------------------------------------------

        private void Move(string agent)
        {
            if (paths[agent].Count == 0) return;
            var cell = paths[agent][0];
            paths[agent].RemoveAt(0);
            cells[agent] = cell;
            moved.Add(agent);
            string region;
            if (scenario.RegionOf.TryGetValue(cell, out region) && region != regions[agent])
            {
                Emit("leave", agent).Location = regions[agent];
                Emit("enter", agent).Location = region;
                regions[agent] = region;
            }
        }

        private string Take(string agent, string item)
        {
            Where where;
            if (item == null || !items.TryGetValue(item, out where)) return "unknown id '" + item + "': no such item";
            if (holding[agent] != null) return "hands full: " + agent + " holds '" + holding[agent] + "'";
            if (where.Holder != null) return "item held by " + where.Holder;
            var location = LocationOf(where.Location);
            if (location == null || !cells[agent].Near(Pt.Of(location.Cell)))
                return "item not there: '" + item + "' is at " + where.Location;
            var e = Emit("take", agent);
            e.Item = item;
            e.Location = where.Location;
            where.Location = null;
            where.Holder = agent;
            holding[agent] = item;
            return null;
        }

        private string Drop(string agent, string locationId)
        {
            var item = holding[agent];
            var location = LocationOf(locationId);
            if (item == null) return "hands empty";
            if (location == null || !cells[agent].Near(Pt.Of(location.Cell))) return "out of reach: location " + locationId;
            var here = items.Values.Count(w => w.Location == locationId);
            if (location.Capacity.HasValue && here >= location.Capacity.Value)
                return "location full: " + locationId + " holds at most " + location.Capacity.Value;
            items[item] = new Where { Location = locationId };
            holding[agent] = null;
            playing[agent] = false;
            var e = Emit("drop", agent);
            e.Item = item;
            e.Location = locationId;
            return null;
        }

        private void Hand(string giver, string receiver)
        {
            var item = holding[giver];
            holding[giver] = null;
            playing[giver] = false;
            holding[receiver] = item;
            items[item].Holder = receiver;
            var e = Emit("give", giver);
            e.Item = item;
            e.Target = receiver;
        }

        // ----- the tick --------------------------------------------------------------------

        public void Step()
        {
            Tick++;
            Events = new List<Event>();
            Statuses = new List<CommandStatus>();
            moved = new HashSet<string>();
            foreach (var id in peopleOrder) UpdatePerson(people[id]);
            UpdateRobot();
            var idle = running == null && queue.Count == 0;
            var still = people.Values.All(p => p.Finished) && idle;
            quiet = still ? quiet + 1 : 0;
            if (quiet >= settle || Tick >= maxTicks) Done = true;
        }

        private void Waypoint(string agent, string label)
        {
            labels.Add(agent + ":" + label);
            var e = Emit("waypoint", agent);
            e.Label = label;
            e.Location = regions[agent];
        }

        private void Complete(Person person, string label)
        {
            if (!string.IsNullOrEmpty(label)) Waypoint(person.Id, label);
            person.Index++;
            person.Started = false;
        }

        private void UpdatePerson(Person person)
        {
            var agent = person.Id;
            while (person.Index < person.Plan.Count)
            {
                var step = person.Step;
                var what = (string)step["do"];
                var label = (string)step["label"];
                if (what == "enter" || what == "goto")
                {
                    if (!person.Started)
                    {
                        person.Started = true;
                        HashSet<Pt> goals;
                        if (what == "enter")
                            goals = new HashSet<Pt>(scenario.RegionOf.Where(kv => kv.Value == (string)step["region"]).Select(kv => kv.Key));
                        else if (step["location"] != null)
                            goals = new HashSet<Pt> { Pt.Of(LocationOf((string)step["location"]).Cell) };
                        else if (step["cell"] != null)
                            goals = new HashSet<Pt> { new Pt((int)step["cell"][0], (int)step["cell"][1]) };
                        else goals = PlaySpots();
                        paths[agent] = Bfs(cells[agent], goals) ?? new List<Pt>();
                    }
                    if (paths[agent].Count > 0)
                    {
                        Move(agent);
                        if (paths[agent].Count > 0) return;
                        Complete(person, label);
                        return;
                    }
                    Complete(person, label);
                    continue;
                }
                if (what == "take" || what == "drop")
                {
                    var here = LocationAt(cells[agent]);
                    string reason;
                    if (what == "take") reason = Take(agent, (string)step["item"]);
                    else reason = here == null ? "no spot here" : Drop(agent, here.Id);
                    Complete(person, reason == null ? label : null);
                    return;
                }
                if (!person.Started)
                {
                    person.Started = true;
                    person.Left = (int?)step["ticks"] ?? 0;
                    if (what == "play")
                    {
                        if (holding[agent] == null)
                        {
                            Complete(person, null);
                            continue;
                        }
                        playing[agent] = true;
                        var spot = LocationAt(cells[agent]);
                        var e = Emit("play", agent);
                        e.Item = holding[agent];
                        e.Location = spot == null ? null : spot.Id;
                    }
                    if (what == "use")
                    {
                        Where where;
                        var itemId = (string)step["item"];
                        var location = items.TryGetValue(itemId, out where) ? LocationOf(where.Location) : null;
                        if (location == null || !location.Use || !cells[agent].Near(Pt.Of(location.Cell)))
                        {
                            Complete(person, null);
                            continue;
                        }
                        playing[agent] = true;
                        var e = Emit("use", agent);
                        e.Item = itemId;
                        e.Location = where.Location;
                    }
                    if (!string.IsNullOrEmpty(label)) Waypoint(agent, label);
                    return;
                }
                if (what == "play" && !playing[agent])
                {
                    Complete(person, null);
                    continue;
                }
                if (step["ticks"] != null)
                {
                    person.Left--;
                    if (person.Left > 0) return;
                }
                else if (step["until"] != null)
                {
                    if (!labels.Contains((string)step["until"])) return;
                }
                else return;
                if (what == "play" || what == "use")
                {
                    playing[agent] = false;
                    Emit("stop", agent).Item = what == "play" ? holding[agent] : (string)step["item"];
                }
                person.Index++;
                person.Started = false;
            }
        }

        // ----- the robot -------------------------------------------------------------------

        /// <summary>A command arrived: accept (queue) it or fail it at once.</summary>
        public void Receive(RobotCommand command)
        {
            var action = command.Action;
            if (command.Robot != Robot) { Status(command, CommandState.Failed, "unknown robot '" + command.Robot + "'"); return; }
            if (!RobotActs) { Status(command, CommandState.Failed, "robot '" + Robot + "' only observes"); return; }
            if (seenIds.Contains(command.Id)) { Status(command, CommandState.Failed, "duplicate command id '" + command.Id + "'"); return; }
            seenIds.Add(command.Id);
            var cancel = action as Cancel;
            if (cancel != null)
            {
                var victim = running != null && running.Id == cancel.Command ? running : queue.FirstOrDefault(c => c.Id == cancel.Command);
                if (victim == null) { Status(command, CommandState.Failed, "no queued or running command '" + cancel.Command + "'"); return; }
                if (victim == running)
                {
                    running = null;
                    paths[Robot] = new List<Pt>();
                }
                else queue.Remove(victim);
                Status(command, CommandState.Accepted);
                Status(victim, CommandState.Cancelled, "cancelled by '" + command.Id + "'");
                Status(command, CommandState.Succeeded);
                return;
            }
            var problem = Check(action);
            if (problem != null) { Status(command, CommandState.Failed, problem); return; }
            Status(command, CommandState.Accepted);
            queue.AddLast(command);
        }

        private string Check(RobotAction action)
        {
            var navigate = action as Navigate;
            if (navigate != null)
                return scenario.Walkable.Contains(Pt.Of(navigate.Cell)) ? null : "not walkable: (" + navigate.Cell.Col + "," + navigate.Cell.Row + ")";
            var pick = action as Pick;
            if (pick != null) return items.ContainsKey(pick.Item) ? null : "unknown id '" + pick.Item + "': no such item";
            var place = action as Place;
            if (place != null) return LocationOf(place.Location) != null ? null : "unknown id '" + place.Location + "'";
            var give = action as Give;
            if (give != null) return people.ContainsKey(give.Person) ? null : "unknown id '" + give.Person + "': no such person";
            var say = action as Say;
            if (say != null) return people.ContainsKey(say.Person) ? null : "unknown id '" + say.Person + "': no such person";
            var request = action as Request;
            if (request != null) return people.ContainsKey(request.Person) ? null : "unknown id '" + request.Person + "'";
            var ask = action as Ask;  // from 1.6
            if (ask != null) return people.ContainsKey(ask.Person) ? null : "unknown id '" + ask.Person + "': no such person";
            return "unknown command kind '" + action.Kind + "'";
        }

        private void UpdateRobot()
        {
            if (Robot == null) return;
            if (running == null)
            {
                if (queue.Count == 0) return;
                running = queue.First.Value;
                queue.RemoveFirst();
                Status(running, CommandState.Running);
                var go = running.Action as Navigate;
                if (go != null)
                {
                    var path = Bfs(cells[Robot], new HashSet<Pt> { Pt.Of(go.Cell) });
                    if (path == null) { Finish(CommandState.Failed, "unreachable"); return; }
                    paths[Robot] = path;
                }
                // no return: the work starts this tick, as in sim2d (a lost tick lets people walk off)
            }
            var me = Robot;
            var action = running.Action;
            string reason = null;
            if (action is Navigate)
            {
                Move(me);
                if (paths[me].Count == 0) Finish(CommandState.Succeeded);
                return;
            }
            if (action is Pick) reason = Take(me, ((Pick)action).Item);
            else if (action is Place) reason = Drop(me, ((Place)action).Location);
            else if (action is Give)
            {
                var person = ((Give)action).Person;
                if (holding[me] == null) reason = "hands empty";
                else if (!cells[me].Near(cells[person])) reason = "out of reach: " + person;
                else if (holding[person] != null) reason = person + "'s hands are full";
                if (reason == null)
                {
                    Hand(me, person);
                    people[person].Replace(Person.Do("goto"), Person.Do("play"));
                }
            }
            else if (action is Say) reason = Tell(me, (Say)action);
            else if (action is Ask)
            {
                AskOf(me, (Ask)action);
                return;
            }
            else
            {
                var request = (Request)action;
                var person = request.Person;
                if (holding[person] != request.Item) reason = person + " does not hold '" + request.Item + "'";
                else if (!cells[me].Near(cells[person])) reason = "out of reach: " + person;
                else
                {
                    var answer = people[person].Answers;
                    var asked = Emit("request", me);
                    asked.Item = request.Item;
                    asked.Target = person;
                    asked.Offer = request.Offer;
                    var replied = Emit("reply", person);
                    replied.Item = request.Item;
                    replied.Target = me;
                    replied.Answer = answer;
                    if (answer)
                    {
                        Hand(person, me);
                        people[person].Replace(Person.Do("wait"));
                    }
                    Finish(CommandState.Succeeded, "", answer);
                    return;
                }
            }
            Finish(reason != null ? CommandState.Failed : CommandState.Succeeded, reason ?? "");
        }

        // The robot's ask (1.6), within earshot: the person says truthfully what they want
        // (an open question when Item is null): an "ask" event, then an "answer" event.
        private void AskOf(string me, Ask ask)
        {
            var person = ask.Person;
            if (!cells[me].WithinEarshot(cells[person]) && regions[me] != regions[person])
            {
                Finish(CommandState.Failed, "out of earshot: " + person);
                return;
            }
            var wanted = people[person].Wants;
            var asked = Emit("ask", me);
            asked.Item = ask.Item;
            asked.Target = person;
            var answered = Emit("answer", person);
            answered.Target = me;
            answered.Item = ask.Item ?? wanted;
            var wants = ask.Item != null ? ask.Item == wanted : wanted != null;
            answered.Answer = wants;
            Finish(CommandState.Succeeded, "", wants);
        }

        private string Tell(string me, Say say)
        {
            var person = say.Person;
            if (!cells[me].WithinEarshot(cells[person]) && regions[me] != regions[person]) return "out of earshot: " + person;
            if (say.Topic != SayTopic.Location)
            {
                var e = Emit("say", me);
                e.Item = say.Item;
                e.Target = person;
                e.Detail = "occupied by " + say.Holder;
                return null;
            }
            var told = new List<Told> { new Told { Item = say.Item, Location = say.Location } };
            if (say.Also != null) told.AddRange(say.Also);  // from 1.6: more items in the same utterance
            var who = people[person];
            foreach (var t in told)  // one event per item told, all on this tick
            {
                var e = Emit("say", me);
                e.Item = t.Item;
                e.Target = person;
                e.Location = t.Location;
                if (t.Item == who.Wants && holding[person] == null)
                    who.Replace(Person.Do("goto", "location", t.Location), Person.Do("take", "item", t.Item),
                        Person.Do("goto"), Person.Do("play"));
            }
            return null;
        }

        private void Finish(string state, string reason = "", bool? answer = null)
        {
            Status(running, state, reason, answer);
            running = null;
        }
    }
}
